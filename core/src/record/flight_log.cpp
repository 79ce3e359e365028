#include "record/flight_log.hpp"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <ctime>

#include <fmt/format.h>
#include <spdlog/sinks/base_sink.h>

namespace tern::core {

namespace {
constexpr std::size_t kChunkBytes = 256 * 1024;
constexpr std::size_t kMaxQueuedBytes = 64 * 1024 * 1024;

/// The host's text log: one write(2) per line, so that a killed process keeps every line.
class TextSink final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  TextSink(fs::path path, LogHealth& health) : file_(std::move(path), health) {}

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    spdlog::memory_buf_t line;
    formatter_->format(msg, line);
    file_.append(std::string_view(line.data(), line.size()));
  }
  void flush_() override {}

 private:
  LogFile file_;
};

// Row formatting writes into a pre-sized char buffer with std::to_chars (shortest round-trip
// for floating point, so a logged double reads back bit-exact): about twice as fast as
// fmt::format_to through a back_inserter, and the writer thread shares the flight's core when
// the process is pinned to one.
constexpr std::size_t kMaxCellChars = 32;  // "-1.2345678901234567e-308" and any 64-bit integer fit

char* put_time(char* p, Nanos t) {
  // exact decimal seconds from integer ns: "<s>.<9 digits>"
  if (t < 0) *p++ = '-';
  const std::uint64_t a = t < 0 ? 0ull - static_cast<std::uint64_t>(t) : static_cast<std::uint64_t>(t);
  p = std::to_chars(p, p + 20, a / 1'000'000'000ull).ptr;
  *p++ = '.';
  std::uint64_t frac = a % 1'000'000'000ull;
  for (int i = 8; i >= 0; --i) {
    p[i] = static_cast<char>('0' + frac % 10);
    frac /= 10;
  }
  return p + 9;
}

void append_time(std::string& out, Nanos t) {
  char buf[kMaxCellChars];
  out.append(buf, put_time(buf, t));
}

template <class T>
T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
}  // namespace

FlightLog::FlightLog(fs::path run_dir, ErrorHandler on_error) : dir_(std::move(run_dir)), on_error_(std::move(on_error)) {
  std::error_code ec;
  fs::create_directories(dir_ / "topics", ec);
  if (ec) health_.fail(fmt::format("cannot create the run directory '{}': {}", dir_.string(), ec.message()));
  params_file_ = std::make_unique<LogFile>(dir_ / "params.csv", health_);
  params_file_->append("t [s],parameter,value,source\n");
  writer_ = std::thread([this] { writer_loop(); });
  report();
}

FlightLog::~FlightLog() { close(); }

std::size_t FlightLog::add_topic(const std::string& topic, std::vector<reflect::Column> columns, std::size_t msg_size) {
  auto t = std::make_unique<Topic>();
  t->name = topic;
  t->columns = std::move(columns);
  t->msg_size = msg_size;
  t->file = std::make_unique<LogFile>(dir_ / "topics" / (topic + ".csv"), health_);
  std::string header = "t [s]";
  for (const auto& c : t->columns) header += "," + c.name + " [" + c.unit + "]";
  header += "\n";
  t->file->append(header);
  topics_.push_back(std::move(t));
  report();
  return topics_.size() - 1;
}

void FlightLog::capture(std::size_t index, Nanos t, const void* data) {
  if (health_.failed()) return;  // nothing more is written: no need to keep it
  Topic& tp = *topics_[index];
  const std::size_t n = tp.pending.size();
  tp.pending.resize(n + sizeof(Nanos) + tp.msg_size);
  std::memcpy(tp.pending.data() + n, &t, sizeof t);
  std::memcpy(tp.pending.data() + n + sizeof t, data, tp.msg_size);
  if (tp.pending.size() >= kChunkBytes) hand_over(index, tp.pending);
}

void FlightLog::param(Nanos t, const std::string& name, const std::string& value, const std::string& source) {
  if (health_.failed()) return;
  std::string row;
  append_time(row, t);
  auto put_cell = [&row](const std::string& s) {  // CSV quoting (RFC 4180) when needed
    row.push_back(',');
    if (s.find_first_of(",\"\n") == std::string::npos) {
      row.append(s);
      return;
    }
    row.push_back('"');
    for (char c : s) {
      if (c == '"') row.push_back('"');
      row.push_back(c);
    }
    row.push_back('"');
  };
  put_cell(name);
  put_cell(value);
  put_cell(source);
  row.push_back('\n');
  params_pending_.insert(params_pending_.end(), row.begin(), row.end());
}

void FlightLog::hand_over(std::size_t topic, std::vector<char>& buf) {
  if (buf.empty()) return;
  std::unique_lock lk(mu_);
  cv_space_.wait(lk, [&] { return queued_bytes_ < kMaxQueuedBytes; });
  queued_bytes_ += buf.size();
  Chunk c{topic, {}};
  c.bytes.swap(buf);
  // frequent flushes hand over small buffers: the next one gets room for a little more
  buf.reserve(std::min(c.bytes.size() * 2, kChunkBytes) + 4096);
  queue_.push_back(std::move(c));
  lk.unlock();
  cv_.notify_one();
}

void FlightLog::flush() {
  report();
  if (health_.failed()) return;
  for (std::size_t i = 0; i < topics_.size(); ++i) hand_over(i, topics_[i]->pending);
  hand_over(SIZE_MAX, params_pending_);
}

void FlightLog::write_file(const std::string& name, const std::string& text) {
  write_file_atomically(dir_ / name, text, health_);
  report();
}

std::shared_ptr<spdlog::sinks::sink> FlightLog::text_sink(const std::string& name) {
  auto sink = std::make_shared<TextSink>(dir_ / name, health_);
  sink->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%l] %n: %v");
  report();
  return sink;
}

void FlightLog::report() {
  if (!on_error_) return;
  if (auto e = health_.take_unreported()) on_error_(fmt::format("flight log: {}; logging stopped, the flight goes on", *e));
}

std::size_t FlightLog::format(const Topic& t, const std::vector<char>& bytes, std::unique_ptr<char[]>& out, std::size_t& capacity) const {
  const std::size_t rec = sizeof(Nanos) + t.msg_size;
  const std::size_t rows = bytes.size() / rec;
  const std::size_t row_max = (t.columns.size() + 1) * (kMaxCellChars + 1) + 1;
  if (rows * row_max > capacity) {
    capacity = rows * row_max;
    out = std::make_unique_for_overwrite<char[]>(capacity);  // no zero-filling: every byte used is written
  }
  char* p = out.get();
  char* const end = p + capacity;
  for (std::size_t off = 0; off + rec <= bytes.size(); off += rec) {
    const char* r = bytes.data() + off;
    p = put_time(p, load<Nanos>(r));
    const char* m = r + sizeof(Nanos);
    for (const auto& c : t.columns) {
      const char* v = m + c.offset;
      *p++ = ',';
      switch (c.kind) {
        case reflect::Scalar::f64: p = std::to_chars(p, end, load<double>(v)).ptr; break;
        case reflect::Scalar::f32: p = std::to_chars(p, end, load<float>(v)).ptr; break;
        case reflect::Scalar::i64: p = std::to_chars(p, end, load<std::int64_t>(v)).ptr; break;
        case reflect::Scalar::i32: p = std::to_chars(p, end, load<std::int32_t>(v)).ptr; break;
        case reflect::Scalar::i16: p = std::to_chars(p, end, load<std::int16_t>(v)).ptr; break;
        case reflect::Scalar::i8: p = std::to_chars(p, end, static_cast<int>(load<std::int8_t>(v))).ptr; break;
        case reflect::Scalar::u64: p = std::to_chars(p, end, load<std::uint64_t>(v)).ptr; break;
        case reflect::Scalar::u32: p = std::to_chars(p, end, load<std::uint32_t>(v)).ptr; break;
        case reflect::Scalar::u16: p = std::to_chars(p, end, load<std::uint16_t>(v)).ptr; break;
        case reflect::Scalar::u8: p = std::to_chars(p, end, static_cast<unsigned>(load<std::uint8_t>(v))).ptr; break;
        case reflect::Scalar::boolean: *p++ = load<std::uint8_t>(v) ? '1' : '0'; break;
      }
    }
    *p++ = '\n';
  }
  return static_cast<std::size_t>(p - out.get());
}

void FlightLog::writer_loop() {
  std::unique_ptr<char[]> text;
  std::size_t capacity = 0;
  for (;;) {
    Chunk c;
    {
      std::unique_lock lk(mu_);
      cv_.wait(lk, [&] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) {  // stop_ and drained
        timespec ts{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
        writer_cpu_s_ = static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
        return;
      }
      c = std::move(queue_.front());
      queue_.pop_front();
    }
    if (!health_.failed()) write_chunk(c, text, capacity);
    {
      std::lock_guard lk(mu_);
      queued_bytes_ -= c.bytes.size();
    }
    cv_space_.notify_all();
  }
}

void FlightLog::write_chunk(const Chunk& c, std::unique_ptr<char[]>& text, std::size_t& capacity) {
  if (c.topic == SIZE_MAX) {
    params_file_->append(std::string_view(c.bytes.data(), c.bytes.size()));
    return;
  }
  Topic& t = *topics_[c.topic];
  const std::size_t n = format(t, c.bytes, text, capacity);
  t.file->append(std::string_view(text.get(), n));
}

void FlightLog::close() {
  if (closed_) return;
  closed_ = true;
  flush();
  {
    std::lock_guard lk(mu_);
    stop_ = true;
  }
  cv_.notify_one();
  if (writer_.joinable()) writer_.join();
  for (auto& t : topics_) t->file.reset();
  params_file_.reset();
  report();
}

}  // namespace tern::core
