#include "flight_log.hpp"

#include <cstring>

#include <fmt/format.h>

#include "error.hpp"

namespace tern::core {

namespace {
constexpr std::size_t kChunkBytes = 256 * 1024;
constexpr std::size_t kMaxQueuedBytes = 64 * 1024 * 1024;

std::FILE* open_or_throw(const fs::path& p) {
  std::FILE* f = std::fopen(p.c_str(), "wb");
  if (f == nullptr) throw ConfigError(fmt::format("cannot write '{}': {}", p.string(), std::strerror(errno)));
  return f;
}

void append_time(std::string& out, Nanos t) {
  // exact decimal seconds from integer ns
  const bool neg = t < 0;
  const std::uint64_t a = neg ? static_cast<std::uint64_t>(-t) : static_cast<std::uint64_t>(t);
  fmt::format_to(std::back_inserter(out), "{}{}.{:09d}", neg ? "-" : "", a / 1'000'000'000ull, a % 1'000'000'000ull);
}

template <class T>
T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
}  // namespace

FlightLog::FlightLog(fs::path run_dir) : dir_(std::move(run_dir)) {
  std::error_code ec;
  fs::create_directories(dir_ / "topics", ec);
  if (ec) throw ConfigError(fmt::format("cannot create log directory '{}': {}", dir_.string(), ec.message()));
  params_file_ = open_or_throw(dir_ / "params.csv");
  std::fputs("t [s],parameter,value,source\n", params_file_);
  std::fflush(params_file_);
  writer_ = std::thread([this] { writer_loop(); });
}

FlightLog::~FlightLog() { close(); }

std::size_t FlightLog::add_topic(const std::string& topic, std::vector<reflect::Column> columns, std::size_t msg_size) {
  auto t = std::make_unique<Topic>();
  t->name = topic;
  t->columns = std::move(columns);
  t->msg_size = msg_size;
  t->file = open_or_throw(dir_ / "topics" / (topic + ".csv"));
  std::string header = "t [s]";
  for (const auto& c : t->columns) header += "," + c.name + " [" + c.unit + "]";
  header += "\n";
  std::fputs(header.c_str(), t->file);
  std::fflush(t->file);
  t->pending.reserve(kChunkBytes + 4096);
  topics_.push_back(std::move(t));
  return topics_.size() - 1;
}

void FlightLog::capture(std::size_t index, Nanos t, const void* data) {
  Topic& tp = *topics_[index];
  const std::size_t n = tp.pending.size();
  tp.pending.resize(n + sizeof(Nanos) + tp.msg_size);
  std::memcpy(tp.pending.data() + n, &t, sizeof t);
  std::memcpy(tp.pending.data() + n + sizeof t, data, tp.msg_size);
  if (tp.pending.size() >= kChunkBytes) hand_over(index, tp.pending);
}

void FlightLog::param(Nanos t, const std::string& name, const std::string& value, const std::string& source) {
  std::string row;
  append_time(row, t);
  auto quote = [](const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += (c == '"') ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
  };
  row += "," + quote(name) + "," + quote(value) + "," + quote(source) + "\n";
  params_pending_.insert(params_pending_.end(), row.begin(), row.end());
}

void FlightLog::hand_over(std::size_t topic, std::vector<char>& buf) {
  if (buf.empty()) return;
  std::unique_lock lk(mu_);
  cv_space_.wait(lk, [&] { return queued_bytes_ < kMaxQueuedBytes; });
  queued_bytes_ += buf.size();
  Chunk c{topic, {}};
  c.bytes.swap(buf);
  queue_.push_back(std::move(c));
  buf.reserve(topic == SIZE_MAX ? 4096 : kChunkBytes + 4096);
  lk.unlock();
  cv_.notify_one();
}

void FlightLog::flush() {
  for (std::size_t i = 0; i < topics_.size(); ++i) hand_over(i, topics_[i]->pending);
  hand_over(SIZE_MAX, params_pending_);
}

void FlightLog::write_file(const std::string& name, const std::string& text) {
  const fs::path p = dir_ / name;
  const fs::path tmp = dir_ / (name + ".tmp");
  std::FILE* f = open_or_throw(tmp);
  std::fwrite(text.data(), 1, text.size(), f);
  std::fclose(f);
  fs::rename(tmp, p);  // a killed process leaves the old file or the new one, never half
}

void FlightLog::format(const Topic& t, const std::vector<char>& bytes, std::string& out) const {
  const std::size_t rec = sizeof(Nanos) + t.msg_size;
  for (std::size_t off = 0; off + rec <= bytes.size(); off += rec) {
    const char* r = bytes.data() + off;
    append_time(out, load<Nanos>(r));
    const char* m = r + sizeof(Nanos);
    auto it = std::back_inserter(out);
    for (const auto& c : t.columns) {
      const char* p = m + c.offset;
      out.push_back(',');
      switch (c.kind) {
        case reflect::Scalar::f64: fmt::format_to(it, "{}", load<double>(p)); break;
        case reflect::Scalar::f32: fmt::format_to(it, "{}", load<float>(p)); break;
        case reflect::Scalar::i64: fmt::format_to(it, "{}", load<std::int64_t>(p)); break;
        case reflect::Scalar::i32: fmt::format_to(it, "{}", load<std::int32_t>(p)); break;
        case reflect::Scalar::i16: fmt::format_to(it, "{}", load<std::int16_t>(p)); break;
        case reflect::Scalar::i8: fmt::format_to(it, "{}", static_cast<int>(load<std::int8_t>(p))); break;
        case reflect::Scalar::u64: fmt::format_to(it, "{}", load<std::uint64_t>(p)); break;
        case reflect::Scalar::u32: fmt::format_to(it, "{}", load<std::uint32_t>(p)); break;
        case reflect::Scalar::u16: fmt::format_to(it, "{}", load<std::uint16_t>(p)); break;
        case reflect::Scalar::u8: fmt::format_to(it, "{}", static_cast<unsigned>(load<std::uint8_t>(p))); break;
        case reflect::Scalar::boolean: out.push_back(load<std::uint8_t>(p) ? '1' : '0'); break;
      }
    }
    out.push_back('\n');
  }
}

void FlightLog::writer_loop() {
  std::string text;
  for (;;) {
    Chunk c;
    {
      std::unique_lock lk(mu_);
      cv_.wait(lk, [&] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stop_ and drained
      c = std::move(queue_.front());
      queue_.pop_front();
    }
    text.clear();
    std::FILE* f;
    if (c.topic == SIZE_MAX) {
      f = params_file_;
      text.assign(c.bytes.begin(), c.bytes.end());
    } else {
      f = topics_[c.topic]->file;
      format(*topics_[c.topic], c.bytes, text);
    }
    std::fwrite(text.data(), 1, text.size(), f);
    std::fflush(f);
    {
      std::lock_guard lk(mu_);
      queued_bytes_ -= c.bytes.size();
    }
    cv_space_.notify_all();
  }
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
  for (auto& t : topics_) {
    if (t->file) std::fclose(t->file);
    t->file = nullptr;
  }
  if (params_file_) std::fclose(params_file_);
  params_file_ = nullptr;
}

}  // namespace tern::core
