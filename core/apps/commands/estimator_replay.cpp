// core/apps/commands/estimator_replay.cpp: the estimator over a sensor log (estimator_replay.hpp).
#include "commands/estimator_replay.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "commands/commands.hpp"
#include "config/cli_overrides.hpp"
#include "config/error.hpp"
#include "export/mcap_csv_export.hpp"
#include "import/sensor_log_writer.hpp"
#include "replay/replay_source.hpp"
#include "replay/sensor_log_meta.hpp"
#include "replay/table_limits.hpp"

namespace tern::core {

namespace {

/// The replay's mission config: the request's, the flight's own config.yaml, or (a real flight's
/// log) the shipped estimator-only config beside the default mission.
fs::path replay_config(const EstimatorReplay& o) {
  if (!o.config.empty()) return o.config;
  const fs::path own = fs::path(o.log_dir) / "config.yaml";
  if (fs::exists(own)) return own;
  return default_config().parent_path().parent_path() / "replay" / "estimator.yaml";
}

/// True when the replay flies the log's own config.yaml (no --config).
bool log_config(const EstimatorReplay& o) { return o.config.empty() && fs::exists(fs::path(o.log_dir) / "config.yaml"); }

/// For a log without a config.yaml of its own (another simulator's or autopilot's, in the
/// documented format): the IMU's timing its topics/imu.csv implies (import's
/// imu_timing_settings() of its longest interval) for every estimator_ekf instance, each where
/// neither sensor_log.yaml nor the replay's config sets it. Under the defaults an IMU logged at
/// 25 Hz timed out between every two samples (15276 warnings over 611 s) and the estimate was
/// never valid. Reads imu.csv's first column only, after replay's file check (table_limits.hpp); a
/// row it cannot read is left to the replay's reader, whose error names the line.
void apply_imu_timing(MissionConfig& mc, const fs::path& log_dir, const SensorLogSettings& s) {
  const fs::path imu_csv = log_dir / "topics" / "imu.csv";
  if (!fs::exists(imu_csv)) return;  // the replay's reader says it is missing
  check_table_file(imu_csv);         // a directory, a device, a FIFO or more than 1 GiB: its one line, before any read
  std::ifstream in(imu_csv);
  std::string line;
  if (!std::getline(in, line)) return;  // the header
  std::optional<Nanos> last;
  Nanos longest = 0;
  while (std::getline(in, line)) {
    const std::optional<Nanos> t = parse_log_time(line.substr(0, line.find(',')));
    if (!t) return;
    if (last && *t > *last) longest = std::max(longest, *t - *last);
    last = t;
  }
  if (longest == 0) return;
  const YAML::Node settings = imu_timing_settings(longest);
  for (auto& ic : mc.plugins) {
    if (ic.plugin != "estimator_ekf") continue;
    for (const auto& kv : settings) {
      const auto name = kv.first.as<std::string>();
      if (s.estimator.count(name) || ic.params.count(name)) continue;
      ic.params[name] = ParamSetting{kv.second, imu_csv, "estimator." + name, true,
                                     fmt::format("imu.csv's longest interval, {:g} s", to_seconds(longest))};
    }
  }
}

/// A log never runs code (docs/hostile-inputs.md): the log's own config.yaml is a record of the
/// flight, not a trusted file, so its plugin_path is dropped (plugins come from the install,
/// TERN_PLUGIN_PATH and --config) and an instance naming a library by path, or a Python script, is
/// refused before anything is loaded.
void forget_log_code(MissionConfig& mc) {
  mc.plugin_path.clear();
  for (const InstanceConfig& ic : mc.plugins) {
    const bool path = ic.plugin.find('/') != std::string::npos || fs::path(ic.plugin).extension() == ".so";
    const bool script = ic.plugin.rfind("python_", 0) == 0;
    if (!path && !script) continue;
    throw ConfigError(where(mc.file, ic.node["plugin"]) + ic.label() + ".plugin: '" + ic.plugin + "': a log's config.yaml never " +
                      (path ? "loads the library it names" : "runs the Python script it names") +
                      " (plugins come from the install and TERN_PLUGIN_PATH): give --config naming the estimator");
  }
}

}  // namespace

void tables_from_mcap(const fs::path& log_dir) {
  const fs::path mcap = log_dir / "flight.mcap";
  if (fs::exists(log_dir / "topics") || !fs::exists(mcap)) return;
  const CsvExportReport r = export_csv(mcap, log_dir / "topics");
  std::fprintf(stderr, "%zu topic tables exported from %s into topics/ (tern export csv)%s\n", r.rows.size(), mcap.c_str(),
               r.stopped.empty() ? "" : (": the file stops early, " + r.stopped).c_str());
}

FlightResult replay_estimator(const EstimatorReplay& o) {
  tables_from_mcap(o.log_dir);
  MissionConfig mc = load_config(replay_config(o).string());
  if (log_config(o)) forget_log_code(mc);
  mc.phases.clear();  // an estimator alone: no controllers, no phases, no mission
  mc.fallback.reset();
  mc.phase_params.clear();
  mc.mission = YAML::Node();
  // a real flight's log (no config.yaml of its own) is named after its directory
  if (o.config.empty() && !log_config(o)) mc.name = fs::absolute(o.log_dir).lexically_normal().filename().string();
  mc.name = mc.name + "-replay";
  if (mc.log.format == LogFormat::mcap) mc.log.format = LogFormat::both;  // the replay report reads the tables
  if (o.level) mc.log.level = *o.level;
  if (o.estimate_only) {
    mc.log.all_topics = false;
    mc.log.topics = {"state"};
  }
  const SensorLogSettings settings = read_sensor_log_settings(o.log_dir);
  apply_sensor_log_settings(mc, settings);
  if (!log_config(o)) apply_imu_timing(mc, o.log_dir, settings);  // a log from elsewhere: its IMU's rate
  CliOverrides cli;
  if (o.kinematic)
    for (const InstanceConfig& i : mc.plugins)
      if (i.plugin == "estimator_ekf")
        for (const char* update : {"use_normal_force", "use_side_force"}) cli.sets.push_back(i.name + "." + update + "=false");
  cli.sets.insert(cli.sets.end(), o.sets.begin(), o.sets.end());
  apply_overrides(mc, cli);
  HostOptions opt;
  opt.replay = replay_source(fs::absolute(o.log_dir), !o.estimate_only);
  opt.quiet = o.quiet;
  if (o.out_dir) opt.log_dir = fs::path(*o.out_dir);
  Host host(std::move(mc), opt);
  host.build();
  host.set_duration(to_seconds(host.replay_end()));
  install_signal_handlers();
  FlightResult r = host.fly();
  const fs::path meta = fs::path(o.log_dir) / "sensor_log.yaml";
  if (fs::exists(meta)) fs::copy_file(meta, fs::path(r.run_dir) / "sensor_log.yaml", fs::copy_options::overwrite_existing);
  return r;
}

}  // namespace tern::core
