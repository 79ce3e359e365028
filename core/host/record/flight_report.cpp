#include "record/flight_report.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <tuple>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "record/metrics.hpp"
#include "safety/phase_machine.hpp"

namespace tern::core {

namespace {

std::string fmt_ns(double ns) {
  if (ns < 1e3) return fmt::format("{:.0f} ns", ns);
  if (ns < 1e6) return fmt::format("{:.1f} us", ns / 1e3);
  return fmt::format("{:.2f} ms", ns / 1e6);
}

}  // namespace

namespace {

// The simulator's sensor profile (the first instance with a `sensor_profile` parameter; in a
// replay, the recorded config.yaml's, which holds every effective value), "" if none.
std::string sensor_profile(const FlightFacts& f) {
  for (const auto& inst : f.instances) {
    if (const ParamBase* p = inst->plugin->find_param("sensor_profile"); p != nullptr) {
      const ParamValue v = p->value();
      if (const auto* name = std::get_if<std::string>(&v)) return *name;
    }
  }
  for (const auto& inst : f.config.plugins) {
    const auto it = inst.params.find("sensor_profile");
    if (it != inst.params.end() && it->second.node.IsScalar()) return it->second.node.as<std::string>();
  }
  return {};
}

}  // namespace

namespace {

// Phases with their start times and reasons, the controller handovers; preflight_s into `j`.
void phases_json(const PhaseMachine& pm, const PhaseRouter& router, nlohmann::ordered_json& j) {
  auto phases = nlohmann::ordered_json::array();
  phases.push_back({{"phase", std::string(msg::phase_name(pm.first_phase()))}, {"start_s", 0.0}, {"reason", "start of flight"}});
  for (const auto& t : pm.transitions()) {
    phases.push_back({{"phase", std::string(msg::phase_name(t.to))}, {"start_s", to_seconds(t.t)}, {"reason", t.reason}});
    if (t.from == msg::Phase::preflight && t.to == msg::Phase::takeoff && !j.contains("preflight_s"))
      j["preflight_s"] = to_seconds(t.t);  // how long the alignment and arming checks took
  }
  j["phases"] = phases;
  auto h = nlohmann::ordered_json::array();
  for (const auto& x : router.handovers()) h.push_back({{"t_s", to_seconds(x.t)}, {"from", x.from}, {"to", x.to}, {"reason", x.reason}});
  j["controller_handovers"] = h;
  j["fallback_engaged"] = router.fallback_engaged();
}

// FNV-1a of a library's bytes, hex, read once per version of the file (its path, size and
// modification time): every flight's summary names its libraries, and reading them byte by byte
// again at every flight's end cost tern.env.FlightEnv's reset most of its time. A file that
// cannot be read hashes as no bytes, and is not kept.
std::string library_fnv1a(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  using Version = std::tuple<std::uintmax_t, fs::file_time_type, std::string>;
  static std::mutex mu;
  static std::map<std::string, Version> known;  // path -> size, time, hash
  std::error_code size_ec, time_ec;
  const std::uintmax_t size = fs::file_size(path, size_ec);
  const fs::file_time_type time = fs::last_write_time(path, time_ec);
  const bool versioned = !size_ec && !time_ec;
  std::lock_guard lk(mu);
  const auto it = known.find(path.string());
  if (versioned && it != known.end() && std::get<0>(it->second) == size && std::get<1>(it->second) == time) return std::get<2>(it->second);
  std::ifstream lib(path, std::ios::binary);
  std::ostringstream bytes;
  if (lib) bytes << lib.rdbuf();
  reflect::Fnv1a h;
  h.bytes(bytes.str());
  const std::string hex = fmt::format("{:016x}", h.h);
  if (versioned && lib) known[path.string()] = Version{size, time, hex};
  return hex;
}

// Per instance: plugin, library (path and FNV-1a of its bytes), steps, its summary() figures;
// for the instance `stuck` (a step the watchdog gave up on, still running) a note instead.
nlohmann::ordered_json instances_json(const std::vector<std::unique_ptr<Instance>>& instances, const std::string& stuck) {
  auto out = nlohmann::ordered_json::object();
  for (const auto& inst : instances) {
    nlohmann::ordered_json x;
    x["plugin"] = inst->info.name;
    if (!inst->builtin) {
      x["library"] = inst->source.string();
      x["library_fnv1a"] = library_fnv1a(inst->info.path);
    }
    x["steps"] = inst->stats.steps;
    if (inst->cfg.name == stuck)
      x["summary"] = "not read: its step was still running when the flight ended";
    else
      for (const auto& [k, v] : inst->plugin->summary()) x[k] = v;
    out[inst->cfg.name] = x;
  }
  return out;
}

nlohmann::ordered_json metrics_json(const FlightMetrics& fm) {
  nlohmann::ordered_json m;
  m["loops"] = fm.loops();
  m["max_cross_track_m"] = fm.max_cross_track();
  m["max_altitude_error_m"] = fm.max_altitude_error();
  m["window_start_s"] = fm.window_start() < 0 ? nlohmann::ordered_json() : nlohmann::ordered_json(to_seconds(fm.window_start()));
  auto passages = nlohmann::ordered_json::array();
  for (const auto& p : fm.passages()) passages.push_back({{"t_s", to_seconds(p.t)}, {"waypoint", p.index}});
  m["waypoint_passages"] = passages;
  auto rms = [](const FlightMetrics::Rms& r) { return r.n ? nlohmann::ordered_json(r.value()) : nlohmann::ordered_json(); };
  if (fm.has_truth()) {
    m["estimation_frame"] = "truth (the estimator's origin mapped to the simulator's)";
    nlohmann::ordered_json e;
    for (int i = 0; i < FlightMetrics::kEst; ++i) e[FlightMetrics::kEstNames[i]] = rms(fm.estimation()[i]);
    m["estimation_rmse"] = e;
    if (fm.has_gnss()) {
      nlohmann::ordered_json g;
      for (int i = 0; i < FlightMetrics::kGnss; ++i) g[FlightMetrics::kEstNames[i]] = rms(fm.raw_gnss()[i]);
      m["raw_gnss_rmse"] = g;
    }
  }
  nlohmann::ordered_json t;
  for (int i = 0; i < FlightMetrics::kTrk; ++i) t[FlightMetrics::kTrkNames[i]] = rms(fm.tracking()[i]);
  m["tracking_rmse"] = t;
  if (const auto& td = fm.touchdown()) {
    auto num = [](double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); };
    m["landing"] = {{"touchdown_t_s", num(td->t_s)},           {"touchdown_along_m", num(td->along_m)},
                    {"touchdown_across_m", num(td->across_m)}, {"sink_rate_mps", num(td->sink_rate_mps)},
                    {"airspeed_mps", num(td->airspeed_mps)},   {"ground_speed_mps", num(td->ground_speed_mps)},
                    {"roll_deg", num(td->roll_deg)},           {"pitch_deg", num(td->pitch_deg)},
                    {"rollout_m", num(td->rollout_m)},         {"stopped", td->stopped}};
  }
  return m;
}

}  // namespace

std::string summary_json(const FlightFacts& f, const FlightResult& r) {
  nlohmann::ordered_json j;
  j["mission"] = f.config.name;
  j["seed"] = f.seed;
  j["duration_s"] = to_seconds(r.flown);
  j["end_reason"] = r.end_reason;
  if (!r.end_detail.empty()) j["end_detail"] = r.end_detail;
  j["base_rate_hz"] = 1e9 / static_cast<double>(f.base_period);
  if (const std::string profile = sensor_profile(f); !profile.empty()) j["sensor_profile"] = profile;
  if (f.phase_machine) phases_json(*f.phase_machine, f.router, j);
  auto fs = nlohmann::ordered_json::array();
  for (const auto& e : f.failsafes)
    fs.push_back({{"t_s", to_seconds(e.t)}, {"cause", e.cause}, {"action", e.action}, {"detail", e.detail}});
  j["failsafes"] = fs;
  j["instances"] = instances_json(f.instances, r.stuck_instance);
  if (f.metrics) j["metrics"] = metrics_json(*f.metrics);
  if (!r.realtime.is_null()) j["realtime"] = r.realtime;  // paced flights only: wall-clock figures
  return j.dump(2) + "\n";
}

std::string timing_json(const FlightFacts& f, const FlightResult& r) {
  nlohmann::ordered_json j;
  j["flight"] = f.flight;  // the host's count: a served host's flight 2 is a fresh host's flight 1 (summary.json)
  j["wall_s"] = r.wall_s;
  j["real_time_factor"] = r.wall_s > 0 ? to_seconds(r.flown) / r.wall_s : 0.0;
  j["start_to_first_tick_ms"] = f.start_to_first_tick_ms;
  // where the time went: the flight thread (plugins and host loop) and the log writer thread
  j["flight_thread_cpu_s"] = r.flight_cpu_s;
  j["flight_thread_real_time_factor"] = r.flight_cpu_s > 0 ? to_seconds(r.flown) / r.flight_cpu_s : 0.0;
  j["log_writer_cpu_s"] = r.log_cpu_s;
  auto inst_j = nlohmann::ordered_json::object();
  for (const auto& inst : f.instances) {
    const auto& s = inst->stats;
    inst_j[inst->cfg.name] = {{"steps", s.steps},
                              {"mean_ns", s.steps ? static_cast<double>(s.total_ns) / static_cast<double>(s.steps) : 0.0},
                              {"median_ns", s.percentile(0.5)},
                              {"p99_ns", s.percentile(0.99)},
                              {"max_ns", s.max_ns},
                              {"budget_ns", s.budget_ns},
                              {"overruns", s.overruns},
                              {"watchdog_slow_steps", s.slow}};
    for (const auto& [k, v] : inst->plugin->timing()) inst_j[inst->cfg.name][k] = v;
  }
  j["instances"] = inst_j;
  return j.dump(2) + "\n";
}

namespace {

// The ROSplane 2.0 paper's two tables (tracking: command vs estimate; estimation: estimate vs
// truth) beside tern's figures, and the waypoints reached.
std::string metrics_text(const FlightMetrics& fm, const std::string& profile) {
  auto v = [](const FlightMetrics::Rms& x) { return x.n ? fmt::format("{:.2f}", x.value()) : std::string("-"); };
  std::string s;
  const auto& t = fm.tracking();
  bool tracked = false;
  for (const auto& x : t) tracked = tracked || x.n > 0;
  if (tracked) {
    s += fmt::format("\nRMS tracking error, command vs estimate ({} loops; window from {}):\n", fm.loops(),
                     fm.window_start() < 0 ? std::string("never: no full loop") : fmt::format("{:.1f} s", to_seconds(fm.window_start())));
    const std::string row7 = "  {:>12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}";
    s += fmt::format(fmt::runtime(row7 + "\n"), "north m", "east m", "altitude m", "roll deg", "pitch deg", "course deg", "airspeed m/s");
    s += fmt::format(fmt::runtime(row7 + "   tern\n"), v(t[0]), v(t[1]), v(t[2]), v(t[3]), v(t[4]), v(t[5]), v(t[6]));
    s += fmt::format(fmt::runtime(row7 + "   ROSplane 2.0 flight test\n"), "3.05", "3.29", "1.19", "7.55", "3.04", "8.51", "0.58");
  }
  if (fm.has_truth()) {
    const auto& e = fm.estimation();
    s += fmt::format("RMS estimation error, estimate vs truth in the simulator's frame (sensor profile: {}):\n",
                     profile.empty() ? "not a tern simulator" : profile);
    const std::string row8 = "  {:>12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}";
    s += fmt::format(fmt::runtime(row8 + "\n"), "north m", "east m", "altitude m", "roll deg", "pitch deg", "heading deg", "course deg",
                     "airspeed m/s");
    s += fmt::format(fmt::runtime(row8 + "   tern\n"), v(e[0]), v(e[1]), v(e[2]), v(e[3]), v(e[4]), v(e[5]), v(e[6]), v(e[7]));
    if (fm.has_gnss()) {
      const auto& g = fm.raw_gnss();
      s += fmt::format(fmt::runtime(row8 + "   raw GNSS (latest fix vs truth)\n"), v(g[0]), v(g[1]), v(g[2]), "", "", "", "", "");
    }
    s += fmt::format(fmt::runtime(row8 + "   ROSplane 2.0 paper (its estimator, its flight: a reference, not a comparison)\n"), "0.325",
                     "0.258", "0.894", "0.189", "0.074", "-", "0.112", "-");
  }
  s += fmt::format("waypoints reached: {}\n", fm.passages().size());
  if (const auto& td = fm.touchdown()) {
    const std::string aim = std::isfinite(td->along_m)
                                ? fmt::format(", {:+.1f} m along and {:+.1f} m across the touchdown point", td->along_m, td->across_m)
                                : std::string(" (no land item: no touchdown point)");
    s += fmt::format(
        "landing (truth): touchdown at {:.2f} s{}, sink {:.2f} m/s, airspeed {:.1f} m/s, roll {:+.1f} deg, pitch {:+.1f} deg; "
        "rollout {:.1f} m{}\n",
        td->t_s, aim, td->sink_rate_mps, td->airspeed_mps, td->roll_deg, td->pitch_deg, td->rollout_m, td->stopped ? ", stopped" : "");
  }
  return s;
}

}  // namespace

std::string summary_text(const FlightFacts& f, const FlightResult& r) {
  std::string s = fmt::format("\nflight '{}' ended ({}) at t = {:.2f} s after {:.2f} s wall ({:.0f}x real time)\n", f.config.name,
                              r.end_reason, to_seconds(r.flown), r.wall_s, r.wall_s > 0 ? to_seconds(r.flown) / r.wall_s : 0.0);
  if (f.phase_machine) {
    s += fmt::format("phases: {} @ 0.00 s", msg::phase_name(f.phase_machine->first_phase()));
    for (const auto& t : f.phase_machine->transitions()) s += fmt::format(", {} @ {:.2f} s", msg::phase_name(t.to), to_seconds(t.t));
    s += "\n";
  }
  s += fmt::format("  {:<16} {:>9} {:>10} {:>10} {:>10} {:>9}\n", "instance", "steps", "median", "p99", "max", "overruns");
  for (const auto& inst : f.instances) {
    const auto& st = inst->stats;
    s += fmt::format("  {:<16} {:>9} {:>10} {:>10} {:>10} {:>9}\n", inst->cfg.name, st.steps, fmt_ns(st.percentile(0.5)),
                     fmt_ns(st.percentile(0.99)), fmt_ns(st.max_ns), st.overruns);
    if (st.slow > 0) s += fmt::format("      {} steps over the watchdog's soft budget\n", st.slow);
  }
  // one line per plugin that has something to say; every figure is in summary.json
  for (const auto& inst : f.instances)
    if (const std::string h = inst->plugin->health(); !h.empty()) s += fmt::format("{}: {}\n", inst->cfg.name, h);
  if (f.metrics) s += metrics_text(*f.metrics, sensor_profile(f));
  s += r.realtime_line;
  s += fmt::format("log: {}\n", r.run_dir.string());
  if (!r.end_detail.empty()) s += fmt::format("FLIGHT ENDED EARLY ({}): {}\n", r.end_reason, r.end_detail);
  return s;
}

int exit_status(const FlightResult& r) {
  if (!r.ok) return 1;
  if (!r.log_error.empty()) return 3;  // flown, but the log is incomplete
  if (r.end_reason == "SIGINT") return 130;
  if (r.end_reason == "SIGTERM") return 143;
  if (r.end_reason == "SIGHUP") return 129;
  return 0;
}

}  // namespace tern::core
