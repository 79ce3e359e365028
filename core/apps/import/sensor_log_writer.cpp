#include "import/sensor_log_writer.hpp"

#include <cstdlib>

#include <fmt/format.h>

namespace tern::core {

namespace fs = std::filesystem;

namespace {

/// out_dir, once it is known to be absent or an empty directory.
fs::path checked_out_dir(const fs::path& out_dir) {
  std::error_code ec;
  if (fs::exists(out_dir, ec)) {
    if (!fs::is_directory(out_dir, ec)) throw ImportError(fmt::format("{}: exists and is not a directory", out_dir.string()));
    if (!fs::is_empty(out_dir, ec))
      throw ImportError(fmt::format("{}: exists and is not empty (choose a new directory)", out_dir.string()));
  }
  fs::create_directories(out_dir / "topics", ec);
  if (ec) throw ImportError(fmt::format("{}: cannot create it: {}", out_dir.string(), ec.message()));
  return out_dir;
}

/// A number as its shortest round-trip text (0.21, not yaml-cpp's 0.20999999999999999); any
/// other node as it is.
YAML::Node shortest(const YAML::Node& v) {
  if (!v.IsScalar()) return v;
  const std::string& text = v.Scalar();
  char* end = nullptr;
  const double d = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) return v;
  return YAML::Node(fmt::format("{}", d));
}

std::string meta_yaml(const SensorLogMeta& meta, const std::string& origin) {
  YAML::Emitter y;
  y << YAML::BeginMap;
  y << YAML::Key << "tern_sensor_log" << YAML::Value << 1;
  y << YAML::Key << "source" << YAML::Value << YAML::DoubleQuoted << meta.source;
  if (!origin.empty()) y << YAML::Key << "origin" << YAML::Value << YAML::DoubleQuoted << origin;
  if (!meta.date.empty()) y << YAML::Key << "date" << YAML::Value << meta.date;
  y << YAML::Key << "aircraft" << YAML::Value << YAML::DoubleQuoted << meta.aircraft;
  if (meta.estimator.IsMap() && meta.estimator.size() > 0) {
    y << YAML::Key << "estimator" << YAML::Value << YAML::BeginMap;
    for (const auto& kv : meta.estimator) y << YAML::Key << kv.first << YAML::Value << shortest(kv.second);
    y << YAML::EndMap;
  }
  if (meta.airborne)
    y << YAML::Key << "airborne" << YAML::Value << YAML::Flow << YAML::BeginSeq << fmt::format("{}", meta.airborne->first)
      << fmt::format("{}", meta.airborne->second) << YAML::EndSeq;
  if (!meta.notes.empty()) {
    y << YAML::Key << "notes" << YAML::Value << YAML::BeginSeq;
    for (const auto& n : meta.notes) y << YAML::DoubleQuoted << n;
    y << YAML::EndSeq;
  }
  y << YAML::EndMap;
  return std::string(y.c_str()) + "\n";
}

}  // namespace

SensorLogWriter::SensorLogWriter(const fs::path& out_dir) : dir_(checked_out_dir(out_dir)), log_(dir_) {
  if (const std::string e = log_.error(); !e.empty()) throw ImportError(fmt::format("{}: {}", dir_.string(), e));
}

SensorLogWriter::~SensorLogWriter() = default;  // the flight log closes itself (an unfinished log has no sensor_log.yaml)

SensorLogWriter::Topic& SensorLogWriter::topic_slot(std::string_view topic, std::vector<reflect::Column> columns, std::size_t size,
                                                    std::uint64_t fingerprint) {
  auto it = topics_.find(topic);
  if (it == topics_.end()) {
    Topic t;
    t.index = log_.add_topic(std::string(topic), std::move(columns), size);
    t.fingerprint = fingerprint;
    it = topics_.emplace(std::string(topic), t).first;
  } else if (it->second.fingerprint != fingerprint) {
    throw ImportError(fmt::format("sensor log: topic '{}' written with two different message types", topic));
  }
  return it->second;
}

void SensorLogWriter::check_order(std::string_view topic, const Topic& t, Nanos stamp) {
  if (t.rows > 0 && stamp < t.last_stamp)
    throw ImportError(
        fmt::format("sensor log: topic '{}': stamp {} ns is earlier than the previous row's {} ns", topic, stamp, t.last_stamp));
}

std::map<std::string, std::uint64_t> SensorLogWriter::rows() const {
  std::map<std::string, std::uint64_t> r;
  for (const auto& [name, t] : topics_) r[name] = t.rows;
  return r;
}

YAML::Node imu_timing_settings(Nanos max_interval) {
  const double dt = to_seconds(max_interval);
  YAML::Node n(YAML::NodeType::Map);
  n["imu_max_dt"] = std::max(0.05, 1.5 * dt);
  n["imu_timeout"] = std::max(0.02, 2.0 * dt);
  n["imu_reinit_gap"] = std::max(0.5, 5.0 * dt);
  return n;
}

YAML::Node SensorLogWriter::slow_sensor_timeouts() const {
  // s: slower than 2.5 Hz, so 2.5 mean intervals are longer than 1 s, every default time-out of
  // these sensors (0.5-1 s): the setting only ever lengthens one
  constexpr double kSlowInterval = 0.4;
  constexpr double kIntervalsLate = 2.5;  // mean intervals of silence before a time-out
  YAML::Node n(YAML::NodeType::Map);
  for (const char* sensor : {"gnss", "baro", "diff_pressure", "mag"}) {
    const auto it = topics_.find(sensor);
    if (it == topics_.end() || it->second.rows < 2) continue;
    const Topic& t = it->second;
    const double mean = to_seconds(t.last_stamp - t.first_stamp) / static_cast<double>(t.rows - 1);
    if (mean > kSlowInterval) n[std::string(sensor) + "_timeout"] = kIntervalsLate * mean;
  }
  return n;
}

void SensorLogWriter::finish(const SensorLogMeta& meta, const std::vector<std::string>& warnings) {
  if (finished_) return;
  finished_ = true;
  SensorLogMeta m = meta;
  for (const auto& w : warnings) m.notes.push_back(std::string(kImportWarning) + (readable_ ? readable_(w) : w));
  // the settings this log implies, where the importer did not set them itself
  const auto add_unset = [&m](const YAML::Node& settings) {
    for (const auto& kv : settings) {
      if (!m.estimator.IsMap()) m.estimator = YAML::Node(YAML::NodeType::Map);
      if (!m.estimator[kv.first.as<std::string>()]) m.estimator[kv.first.as<std::string>()] = kv.second;
    }
  };
  if (const auto imu = topics_.find("imu"); imu != topics_.end() && imu->second.rows > 1)
    add_unset(imu_timing_settings(imu->second.max_interval));
  add_unset(slow_sensor_timeouts());
  log_.write_file("sensor_log.yaml", meta_yaml(m, origin_));
  log_.close();
  if (const std::string e = log_.error(); !e.empty()) throw ImportError(fmt::format("{}: {}", dir_.string(), e));
  // the flight log's parameter table: a sensor log has no parameters (only its header was written)
  std::error_code ec;
  fs::remove(dir_ / "params.csv", ec);
}

}  // namespace tern::core
