// The replay report: reads the run directory's tables and builds each section
// (replay_report_parts.hpp); the window, the estimator's counters and the validity live here.
#include "replay/replay_report.hpp"

#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "config/error.hpp"
#include "replay/replay_report_parts.hpp"
#include "replay/sensor_log_meta.hpp"

namespace tern::core {

namespace replay_report {

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

void add_sample_time(CsvTable& table) {
  const auto& t = table.at("t");
  std::vector<double> time(t);
  if (table.has("stamp")) {
    const auto& stamp = table.at("stamp");
    bool monotonic = true;
    for (std::size_t k = 0; k < stamp.size() && monotonic; ++k) monotonic = std::isfinite(stamp[k]) && (k == 0 || stamp[k] >= stamp[k - 1]);
    if (monotonic)
      for (std::size_t k = 0; k < stamp.size(); ++k) time[k] = stamp[k] / 1e9;
  }
  table.columns["time"] = std::move(time);
}

ReplayWindow find_window(const RunTables& run) {
  if (auto w = read_airborne_window(run.dir / "sensor_log.yaml"))
    return {w->start_s, w->end_s, fmt::format("sensor_log.yaml airborne: [{}, {}] s", w->start_s, w->end_s)};
  const auto& t = run.state.at("t");
  const ReplayWindow whole{t.front(), t.back(), ""};
  if (!run.gnss) return {whole.start_s, whole.end_s, "the whole replay (no sensor_log.yaml airborne, no gnss.csv)"};
  const auto& tg = run.gnss->at("t");
  const auto& vn = run.gnss->at("vel_n");
  const auto& ve = run.gnss->at("vel_e");
  double first = NAN, last = NAN;
  for (std::size_t k = 0; k < tg.size(); ++k) {
    if (!(std::hypot(vn[k], ve[k]) >= kMinCourseSpeed)) continue;
    if (std::isnan(first)) first = tg[k];
    last = tg[k];
  }
  if (std::isnan(first))
    return {whole.start_s, whole.end_s, "the whole replay (the GNSS horizontal speed never reached 5 m/s; no sensor_log.yaml airborne)"};
  return {first, last, fmt::format("GNSS horizontal speed >= 5 m/s: first fix {:.3f} s to last {:.3f} s (log time t)", first, last)};
}

EstimatorCounters estimator_counters(const nlohmann::ordered_json& summary) {
  EstimatorCounters c;
  if (!summary.contains("instances") || !summary["instances"].is_object()) return c;
  for (const auto& item : summary["instances"].items()) {
    const auto& inst = item.value();  // (not a structured binding: clang 14, make fuzz's, cannot capture one)
    if (!inst.is_object()) continue;
    auto number = [&](const std::string& key) { return inst.contains(key) && inst[key].is_number() ? inst[key].get<double>() : NAN; };
    for (const auto& [key, value] : inst.items()) {
      if (ends_with(key, "_accepted") && value.is_number()) {
        const std::string model = key.substr(0, key.size() - 9);
        c.models.push_back({model, value.get<double>(), number(model + "_rejected"), number(model + "_mean_nis")});
      } else if ((ends_with(key, "_resets") || key == "inflations") && value.is_number()) {
        c.resets.emplace_back(key, value.get<double>());
      }
    }
    if (!c.models.empty()) {
      c.instance = item.key();
      return c;
    }
    c.resets.clear();
  }
  return c;
}

Validity validity(const CsvTable& state, const EstimatorCounters& counters) {
  Validity v;
  v.nan_cells = state.nan_cells;
  v.nan_rows = state.nan_rows;
  const auto& t = state.at("t");
  const auto& valid = state.at("valid");
  std::size_t k0 = 0;
  while (k0 < valid.size() && !(valid[k0] > 0.5)) ++k0;
  for (const auto& [name, n] : counters.resets)
    if (name == "filter_resets" && n > 0) v.filter_resets = static_cast<std::size_t>(n);
  if (k0 < valid.size()) {
    v.first_valid_s = t[k0];
    std::size_t n_valid = 0;
    for (std::size_t k = k0; k < valid.size(); ++k) {
      n_valid += valid[k] > 0.5 ? 1 : 0;
      v.valid_to_invalid += (k > k0 && valid[k - 1] > 0.5 && !(valid[k] > 0.5)) ? 1 : 0;
    }
    v.samples = valid.size() - k0;
    v.share_valid = static_cast<double>(n_valid) / static_cast<double>(v.samples);
  }
  v.divergences = v.valid_to_invalid + v.filter_resets;
  return v;
}

namespace {

nlohmann::ordered_json read_summary(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) return nlohmann::ordered_json::object();
  std::ifstream in(file);
  try {
    return nlohmann::ordered_json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw ConfigError(fmt::format("{}: not JSON ({})", file.string(), e.what()));
  }
}

std::optional<CsvTable> optional_topic(const std::filesystem::path& dir, const std::string& name, const std::vector<std::string>& wanted,
                                       std::vector<std::string>& notes) {
  const auto file = dir / "topics" / (name + ".csv");
  if (!std::filesystem::exists(file)) return std::nullopt;
  CsvTable t = read_csv_table(file, wanted);
  if (!t.partial_last_line.empty()) notes.push_back(t.partial_last_line);
  if (t.rows == 0 || !t.has("t")) return std::nullopt;
  return t;
}

}  // namespace

}  // namespace replay_report

ReplayReport make_replay_report(const std::filesystem::path& run_dir) {
  using namespace replay_report;
  ReplayReport r;
  r.run_dir = run_dir;
  RunTables run;
  run.dir = run_dir;
  const auto state_file = run_dir / "topics" / "state.csv";
  if (!std::filesystem::exists(state_file)) throw ConfigError(run_dir.string() + ": no topics/state.csv (not a replay's run directory?)");
  run.state = read_csv_table(state_file, {"t", "stamp", "p_n", "p_e", "p_d", "v_n", "v_e", "v_d", "phi", "theta", "psi", "w_n", "w_e",
                                          "origin_lat", "origin_lon", "origin_alt", "origin_valid", "valid"});
  if (!run.state.partial_last_line.empty()) r.notes.push_back(run.state.partial_last_line);
  if (run.state.rows == 0) throw ConfigError(state_file.string() + ": no rows (the replay produced no estimate)");
  for (const char* c : {"t", "valid"}) run.state.at(c);  // the columns every section needs: named error if absent
  add_sample_time(run.state);
  run.innovations = optional_topic(run_dir, "innovations", {}, r.notes);
  run.gnss = optional_topic(run_dir, "gnss", {"t", "stamp", "time_of_validity", "fix_type", "lat", "lon", "alt", "vel_n", "vel_e", "vel_d"},
                            r.notes);
  run.reference = optional_topic(run_dir, "reference", {}, r.notes);
  run.imu = optional_topic(run_dir, "imu", {"t", "stamp", "accel_x", "accel_y", "accel_z"}, r.notes);
  run.baro = optional_topic(run_dir, "baro", {"t", "stamp", "pressure"}, r.notes);
  run.mag = optional_topic(run_dir, "mag", {"t", "field_x", "field_y", "field_z"}, r.notes);
  if (run.imu) add_sample_time(*run.imu);
  if (run.baro) add_sample_time(*run.baro);
  if (run.reference) add_sample_time(*run.reference);
  if (std::filesystem::exists(run_dir / "params.csv")) run.params = read_params_csv(run_dir / "params.csv");
  run.summary = read_summary(run_dir / "summary.json");
  r.replay_start_s = run.state.at("t").front();
  r.replay_end_s = run.state.at("t").back();
  r.window = find_window(run);
  r.counters = estimator_counters(run.summary);
  r.rows = row_account(run.summary, r.counters);
  r.validity = validity(run.state, r.counters);
  r.measurements = measurement_reports(run, r.counters, r.window);
  if (!run.innovations) r.measurements_absent = "absent (no topics/innovations.csv)";
  r.reference = compare_reference(run, r.window);
  r.gnss = compare_gnss(run, r.counters, r.window);
  r.wind = wind_report(run, r.window);
  r.specific_force = check_specific_force(run, r.counters, r.window);
  r.mag_field = check_mag_field(run, r);
  r.explanations = explain_anomalies(run, r);
  return r;
}

}  // namespace tern::core
