#include "record/flight_recorder.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <limits>
#include <set>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "graph/scheduler.hpp"
#include "record/log_definitions.hpp"
#include "tern/msg/path.hpp"

namespace tern::core {

fs::path new_run_dir(const fs::path& parent, const std::string& mission) {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%SZ", &tm);
  fs::path dir = parent / (std::string(stamp) + "-" + mission);
  for (int k = 2; fs::exists(dir); ++k) dir = parent / fmt::format("{}-{}-{}", stamp, mission, k);
  return dir;
}

namespace {

// One row of <topic>_items.csv: a waypoint of a logged waypoint list.
struct WaypointItem {
  static constexpr std::string_view type_name = "tern/WaypointItem";
  Nanos stamp = 0;             // the list's stamp
  std::uint32_t revision = 0;  // the list's revision
  std::uint32_t index = 0;     // position in the list
  msg::Waypoint waypoint{};
  template <class V>
  static constexpr void describe(V& v) {
    v(&WaypointItem::stamp, "stamp", "ns");
    v(&WaypointItem::revision, "revision", "");
    v(&WaypointItem::index, "index", "");
  }
};

// WaypointItem's columns, the waypoint's own (reflect::layout skips nested structs) appended.
std::vector<reflect::Column> waypoint_item_columns() {
  std::vector<reflect::Column> cols = reflect::layout<WaypointItem>();
  for (reflect::Column c : reflect::layout<msg::Waypoint>()) {
    c.offset += offsetof(WaypointItem, waypoint);
    cols.push_back(std::move(c));
  }
  return cols;
}

std::string param_text(const ParamValue& v) {
  if (std::holds_alternative<std::string>(v)) return std::get<std::string>(v);
  return to_string(v);
}

}  // namespace

FlightRecorder::FlightRecorder(const fs::path& run_dir, std::shared_ptr<spdlog::sinks::dist_sink_mt> sinks,
                               FlightLog::ErrorHandler on_error, FlightLog::Format format)
    : log_(run_dir, std::move(on_error), format), sinks_(std::move(sinks)), last_flush_(wall_ns()) {
  file_sink_ = log_.text_sink("tern.log");
  sinks_->add_sink(file_sink_);
}

FlightRecorder::~FlightRecorder() {
  sinks_->remove_sink(file_sink_);
  file_sink_->flush();
}

void FlightRecorder::start(const std::string& config_yaml, const std::vector<std::pair<std::string, const ParamBase*>>& params,
                           const std::map<std::string, std::string>& sources) {
  log_.write_file("config.yaml", config_yaml);
  log_.write_file("definitions.json", log_definitions_json());
  for (const auto& [name, p] : params) {
    const auto source = sources.find(name);
    log_.param(0, name, param_text(p->value()), source != sources.end() ? source->second : "default");
  }
}

FlightLog::Format FlightRecorder::format_of(const LogConfig& log) {
  FlightLog::Format f{log.format != LogFormat::mcap, log.format != LogFormat::csv, log.chunk_size, log.ros_channels};
  f.mcap_zstd_level = log.zstd_level.value_or(default_zstd_level(log.level));
  // levels replay and sysid: the ROS-typed copies at the plotting rate, also of the topics kept in full
  if (log.level == LogLevel::replay || log.level == LogLevel::sysid)
    f.mcap_ros_interval_ns = static_cast<std::int64_t>(std::llround(1e9 / log.plot_rate));
  return f;
}

// Measured on the default mission (seed 1, 707 s), pinned to one core, median of 3 (docs/logs.md):
// at level replay, zstd level 2 against 1 gives a 35.7 MB log against 38.2 MB (the 400-Hz IMU
// interleaved with the rest finds more matches) for 0.044 CPU s more; at level full, 127.1 MB
// against 128.9 MB for 0.16 s more, and level 3 hardly shrinks either (doubles barely compress).
int FlightRecorder::default_zstd_level(LogLevel level) { return level == LogLevel::sysid || level == LogLevel::full ? 1 : 2; }

double FlightRecorder::topic_rate(const LogConfig& log, const std::string& topic) {
  // raw sensor topics (and the actuators, an input of the estimator's side-force model) are
  // logged in full but at level decimated, so that a flight can be replayed
  static const std::set<std::string> kReplayInputs = {"imu", "gnss", "baro", "diff_pressure", "mag", "rc", "fcu_status", "actuators"};
  // what system identification needs besides: the simulator's truth and the estimate, every sample
  static const std::set<std::string> kSysidInputs = {"truth", "state"};
  const bool in_full = kReplayInputs.count(topic) || (log.level == LogLevel::sysid && kSysidInputs.count(topic));
  const bool thinned = log.level == LogLevel::replay || log.level == LogLevel::sysid;
  const auto rate_it = log.rates.find(topic);
  const double rate = rate_it != log.rates.end() ? rate_it->second : in_full ? 0.0 : thinned ? log.plot_rate : log.max_rate;
  if (log.level != LogLevel::decimated) return rate;
  return rate > 0 ? std::min(rate, log.decimated_rate) : log.decimated_rate;
}

void FlightRecorder::choose_topics(const PortGraph& graph, const LogConfig& log, const fs::path& config_file, spdlog::logger& warn) {
  const std::set<std::string> wanted(log.topics.begin(), log.topics.end());
  logged_.assign(graph.topics().size(), Logged{});
  if (log.level == LogLevel::summary) return;  // no topic tables (log.topics was checked by the config)
  for (std::size_t k = 0; k < graph.topics().size(); ++k) {
    const GraphTopic& t = graph.topics()[k];
    if (!t.written() || (!log.all_topics && !wanted.count(t.name))) continue;
    Logged& l = logged_[k];
    l.index = log_.add_topic(t.name, t.columns, t.msg_size, t.type_name);
    l.topic = t.name;
    if (t.fingerprint == reflect::fingerprint<msg::WaypointList>())
      l.items = log_.add_topic(t.name + "_items", waypoint_item_columns(), sizeof(WaypointItem), WaypointItem::type_name);
    const double max_rate = topic_rate(log, t.name);
    l.interval = max_rate > 0 ? static_cast<Nanos>(std::llround(1e9 / max_rate)) : 0;
    l.t = std::numeric_limits<Nanos>::min() / 2;
    if (l.interval == 0)
      for (const auto& [node, out] : t.writers) out->keep_history(kBurstDepth);
  }
  for (const auto& w : wanted) {
    const GraphTopic* t = graph.find(w);
    if (t == nullptr || t->writers.empty()) warn.warn("{}: log.topics: no instance publishes topic '{}'", config_file.string(), w);
  }
}

void FlightRecorder::param(Nanos t, const std::string& qualified_name, const ParamBase& p, const std::string& source) {
  log_.param(t, qualified_name, param_text(p.value()), source);
}

void FlightRecorder::capture(const PortGraph& graph, Nanos now) {
  for (std::size_t k = 0; k < logged_.size(); ++k) {
    Logged& l = logged_[k];
    const OutputBase* src = graph.topics()[k].current;
    if (l.index == SIZE_MAX || src == nullptr) continue;
    const std::uint64_t seq = src->sequence();
    if (seq == 0 || (src == l.source && seq == l.seq)) continue;
    if (now - l.t < l.interval) continue;
    // Logged in full: every message since the last capture that the writer still holds (from
    // its first held one at a topic's first capture); another writer taking over (a phase's
    // controller) starts at its latest.
    const bool every = l.interval == 0 && (src == l.source || l.source == nullptr);
    const std::uint64_t next = src == l.source ? l.seq + 1 : src->oldest();
    const std::uint64_t first = every ? std::max(next, src->oldest()) : seq;
    if (every && src == l.source) l.lost += first - next;
    for (std::uint64_t s = first; s <= seq; ++s) write(l, now, src->message(s));
    l.source = src;
    l.seq = seq;
    l.t = now;
  }
}

void FlightRecorder::write(const Logged& l, Nanos now, const void* msg) {
  log_.capture(l.index, now, msg);
  if (l.items == SIZE_MAX) return;
  const auto& list = *static_cast<const msg::WaypointList*>(msg);
  for (std::uint32_t i = 0; i < std::min<std::uint32_t>(list.count, msg::WaypointList::kCapacity); ++i) {
    const WaypointItem row{list.stamp, list.revision, i, list.items[i]};
    log_.capture(l.items, now, &row);
  }
}

void FlightRecorder::flush_if_due(spdlog::logger& text_log) {
  const std::int64_t w = wall_ns();
  if (w - last_flush_ <= FlightLog::kFlushPeriodNs) return;
  log_.flush();
  text_log.flush();
  last_flush_ = w;
}

void FlightRecorder::finish(const FlightFacts& facts, FlightResult& r) {
  log_.write_file("summary.json", summary_json(facts, r));
  log_.close();
  r.log_cpu_s = log_.writer_cpu_s();
  log_.write_file("timing.json", timing_json(facts, r));
  r.log_error = log_.error();
  for (const Logged& l : logged_)
    if (r.log_error.empty() && l.lost > 0)
      r.log_error =
          fmt::format("topic '{}': {} messages not logged: published faster than the log captured them (its writer holds the last {})",
                      l.topic, l.lost, kBurstDepth);
}

}  // namespace tern::core
