#include "record/flight_log.hpp"

#include "ros/cdr_columns.hpp"
#include "csv/csv_rows.hpp"
#include "ros/ros_channels.hpp"

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

Nanos load_time(const char* p) {
  Nanos t;
  std::memcpy(&t, p, sizeof t);
  return t;
}

void append_time(std::string& out, Nanos t) {
  char buf[kMaxCellChars];
  out.append(buf, put_csv_time(buf, t));
}

// Which of the small files written whole go into the MCAP file too (timing.json has wall-clock
// times: the MCAP file stays the same for the same config and seed).
std::string_view attached_media_type(const std::string& name) {
  if (name == "config.yaml") return "application/yaml";
  if (name == "summary.json" || name == "definitions.json") return "application/json";
  return {};
}
}  // namespace

FlightLog::FlightLog(fs::path run_dir, ErrorHandler on_error, Format format)
    : dir_(std::move(run_dir)), on_error_(std::move(on_error)), format_(format) {
  std::error_code ec;
  fs::create_directories(format_.csv ? dir_ / "topics" : dir_, ec);
  if (ec) health_.fail(fmt::format("cannot create the run directory '{}': {}", dir_.string(), ec.message()));
  params_file_ = std::make_unique<LogFile>(dir_ / "params.csv", health_);
  params_text_ = "t [s],parameter,value,source\n";
  params_file_->append(params_text_);
  if (format_.mcap)
    mcap_ =
        std::make_unique<McapWriter>(dir_ / "flight.mcap", health_, McapWriter::Options{format_.mcap_chunk_bytes, format_.mcap_zstd_level});
  writer_ = std::thread([this] { writer_loop(); });
  report();
}

FlightLog::~FlightLog() { close(); }

std::size_t FlightLog::add_topic(const std::string& topic, std::vector<reflect::Column> columns, std::size_t msg_size,
                                 std::string_view type_name) {
  auto t = std::make_unique<Topic>();
  t->name = topic;
  t->columns = std::move(columns);
  t->msg_size = msg_size;
  const std::string header = csv_header(t->columns);
  if (format_.csv) {
    t->file = std::make_unique<LogFile>(dir_ / "topics" / (topic + ".csv"), health_);
    t->file->append(header);
  }
  if (mcap_) {
    const auto schema = mcap_->add_schema(tern_schema_name(type_name, topic), "ros2msg", tern_schema_text(t->columns));
    // the CSV header keeps the names and units `tern export csv` writes
    t->channel = mcap_->add_channel(schema, "/" + topic, "cdr", {{"tern.csv_header", header.substr(0, header.size() - 1)}});
    t->cdr = CdrEncoder(t->columns);
    if (format_.mcap_ros_channels) add_ros_channels(*t, type_name);
  }
  topics_.push_back(std::move(t));
  report();
  return topics_.size() - 1;
}

void FlightLog::add_ros_channels(Topic& t, std::string_view type_name) {
  if (const RosChannelLookup& lookup = ros_channel_lookup())
    if (std::optional<RosChannel> ros = lookup(t.name, type_name)) add_copy(t, std::move(*ros), {{"tern.topic", t.name}});
  if (!scene_) scene_ = std::make_unique<Scene>(format_.scene);
  for (RosChannel& c : scene_->channels_of(t.name, type_name)) {
    const std::string topic = c.topic;
    add_copy(t, std::move(c), {{"tern.scene", topic}});
  }
}

void FlightLog::add_copy(Topic& t, RosChannel ros, const McapWriter::Metadata& metadata) {
  // a channel several topics feed (/tf) and a schema several channels use are written once
  auto id = [this](const std::string& key, auto add) {
    const auto it = copy_ids_.find(key);
    return it != copy_ids_.end() ? it->second : copy_ids_[key] = add();
  };
  const auto schema = id("schema:" + ros.type, [&] { return mcap_->add_schema(ros.type, "ros2msg", ros.schema); });
  const auto channel = id(ros.topic, [&] { return mcap_->add_channel(schema, ros.topic, "cdr", metadata); });
  t.copies.push_back({channel, std::move(ros.encode)});
}

void FlightLog::capture(std::size_t index, Nanos t, const void* data) {
  if (health_.failed()) return;  // nothing more is written: no need to keep it
  Topic& tp = *topics_[index];
  if (tp.file) {
    const std::size_t n = tp.pending.size();
    tp.pending.resize(n + sizeof(Nanos) + tp.msg_size);
    std::memcpy(tp.pending.data() + n, &t, sizeof t);
    std::memcpy(tp.pending.data() + n + sizeof t, data, tp.msg_size);
    if (tp.pending.size() >= kChunkBytes) hand_over(index, tp.pending);
  }
  if (mcap_) {  // one buffer for every topic: the file keeps the order of capture
    std::vector<char>& m = mcap_pending_;
    const std::size_t n = m.size();
    const std::uint64_t topic = index;
    m.resize(n + sizeof topic + sizeof(Nanos) + tp.msg_size);
    std::memcpy(m.data() + n, &topic, sizeof topic);
    std::memcpy(m.data() + n + sizeof topic, &t, sizeof t);
    std::memcpy(m.data() + n + sizeof topic + sizeof t, data, tp.msg_size);
    if (m.size() >= kChunkBytes) hand_over(kMcap, m);
  }
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
  if (mcap_) params_text_ += row;
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
  hand_over(kParams, params_pending_);
  if (mcap_) {  // the open chunk to the kernel, after the rows above
    hand_over(kMcap, mcap_pending_);
    std::vector<char> sync{'\0'};
    hand_over(kSync, sync);
  }
}

void FlightLog::write_file(const std::string& name, const std::string& text) {
  write_file_atomically(dir_ / name, text, health_);
  if (mcap_ && !attached_media_type(name).empty()) attachments_[name] = text;
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
  if (c.topic == kParams) {
    params_file_->append(std::string_view(c.bytes.data(), c.bytes.size()));
    return;
  }
  if (c.topic == kSync) {
    mcap_->sync();
    return;
  }
  if (c.topic == kMcap) {
    write_mcap(c.bytes);
    return;
  }
  Topic& t = *topics_[c.topic];
  if (t.file) {
    const std::size_t n = format_csv_rows(t.columns, t.msg_size, std::string_view(c.bytes.data(), c.bytes.size()), text, capacity);
    t.file->append(std::string_view(text.get(), n));
  }
}

void FlightLog::write_mcap(const std::vector<char>& bytes) {
  McapWriter::Batch batch(*mcap_);
  std::size_t off = 0;
  while (off + sizeof(std::uint64_t) + sizeof(Nanos) <= bytes.size()) {
    std::uint64_t index;
    std::memcpy(&index, bytes.data() + off, sizeof index);
    Topic& t = *topics_[index];
    const Nanos when = load_time(bytes.data() + off + sizeof index);
    const char* msg = bytes.data() + off + sizeof index + sizeof(Nanos);
    cdr_.clear();
    t.cdr.append(msg, cdr_);
    batch.message(t.channel, static_cast<std::uint64_t>(when), cdr_);  // flight time >= 0
    // the same message in its ROS type; the record sits at any offset and the message struct
    // (Eigen members) wants its alignment
    if (!t.copies.empty()) {
      aligned_.resize(t.msg_size / sizeof(std::max_align_t) + 1);
      std::memcpy(aligned_.data(), msg, t.msg_size);
    }
    for (Topic::Copy& copy : t.copies) {
      if (when - copy.last < format_.mcap_ros_interval_ns) continue;
      copy.last = when;
      ros_samples_.clear();
      copy.encode(aligned_.data(), ros_samples_);
      for (const std::string& sample : ros_samples_) batch.message(copy.channel, static_cast<std::uint64_t>(when), sample);
    }
    off += sizeof index + sizeof(Nanos) + t.msg_size;
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
  for (auto& t : topics_) t->file.reset();
  params_file_.reset();
  if (mcap_) {
    attachments_["params.csv"] = params_text_;
    for (const auto& [name, text] : attachments_)  // by name: config.yaml, definitions.json, params.csv, summary.json
      mcap_->attachment(name, name == "params.csv" ? "text/csv" : attached_media_type(name), text, 0);
    mcap_->finish();
  }
  report();
}

}  // namespace tern::core
