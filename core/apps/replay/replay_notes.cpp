// The replay report's explanations (ReportNote): the list in the order the table prints them, and
// the NIS notes (an estimator model's mean NIS outside [kLowNisNote, kHighNisNote]: the setting
// that allows it). The magnetometer, the attitude and the altitude datum have their own files
// (replay_note_mag.cpp, replay_note_attitude.cpp, replay_note_altitude.cpp).
#include <cmath>

#include <fmt/format.h>

#include "replay/replay_report_parts.hpp"

namespace tern::core::replay_report {

namespace {

constexpr double kMinNisSamples = 30.0;  ///< fused samples a model needs for its mean NIS to be explained

std::string param_text(const RunTables& run, const ReplayReport& r, const std::string& name, const char* unit) {
  const auto v = estimator_param(run, r, name);
  return v ? fmt::format("{} = {:g} {}", name, *v, unit) : name;
}

/// What allows the model's noise: its settings, and what kind of measurement it is.
std::string noise_settings(const RunTables& run, const ReplayReport& r, const std::string& model) {
  if (model == "diff_pressure")
    return param_text(run, r, "airspeed_gust_sigma", "m/s") + " of gusts the wind state does not follow and " +
           param_text(run, r, "diff_pressure_noise", "Pa") +
           ", set for turbulence; calm air takes less, docs/replay-your-own-flight.md section 5";
  if (model == "sideslip")
    return "a zero-sideslip pseudo-measurement, not a sensor, whose " + param_text(run, r, "sideslip_noise", "m/s") +
           " of body-y air velocity is a generous allowance";
  if (model == "side_force") return param_text(run, r, "side_force_noise", "m/s^2");
  if (model == "gnss_pos") return param_text(run, r, "gnss_pos_noise_h", "m") + ", " + param_text(run, r, "gnss_accuracy_floor", "m");
  if (model == "gnss_vel") return param_text(run, r, "gnss_vel_noise_h", "m/s") + ", " + param_text(run, r, "gnss_vel_accel_scale", "s");
  if (model == "baro") return param_text(run, r, "baro_noise", "Pa");
  if (model == "mag" || model == "mag_heading") return param_text(run, r, "mag_noise", "T");
  return "its noise settings";
}

std::optional<ReportNote> nis_note(const RunTables& run, const ReplayReport& r, const ModelCounters& m) {
  if (m.accepted + m.rejected < kMinNisSamples || !std::isfinite(m.mean_nis)) return std::nullopt;
  const std::string where = "estimator.models." + m.model;
  if (m.mean_nis < kLowNisNote)
    return ReportNote{{where},
                      fmt::format("mean NIS {:.3f}, below {}: the innovations are smaller than the noise the estimator allows for "
                                  "them ({}); a cautious setting, not a fault of the sensor or the estimate",
                                  m.mean_nis, kLowNisNote, noise_settings(run, r, m.model))};
  if (m.mean_nis > kHighNisNote)
    return ReportNote{{where},
                      fmt::format("mean NIS {:.2f}, above {}: the innovations are larger than the noise the estimator allows ({}), "
                                  "or this sensor disagrees with the others: look (a possible defect)",
                                  m.mean_nis, kHighNisNote, noise_settings(run, r, m.model))};
  return std::nullopt;
}

bool explained(const std::vector<ReportNote>& notes, const std::string& where) {
  for (const auto& n : notes)
    for (const auto& w : n.where)
      if (w == where) return true;
  return false;
}

}  // namespace

std::optional<double> estimator_param(const RunTables& run, const ReplayReport& r, const std::string& name) {
  if (r.counters.instance.empty()) return std::nullopt;
  return run.params.number_at(r.counters.instance + "." + name, r.window.start_s);
}

std::vector<ReportNote> explain_anomalies(const RunTables& run, const ReplayReport& r) {
  std::vector<ReportNote> out;
  if (auto n = magnetometer_note(run, r)) out.push_back(std::move(*n));  // the NIS table's rows come first in the table
  for (const auto& m : r.counters.models)
    if (!explained(out, "estimator.models." + m.model))
      if (auto n = nis_note(run, r, m)) out.push_back(std::move(*n));
  for (auto& n : attitude_notes(run, r)) out.push_back(std::move(n));
  if (auto n = altitude_datum_note(run, r)) out.push_back(std::move(*n));
  if (auto n = mag_field_note(r)) out.push_back(std::move(*n));
  return out;
}

}  // namespace tern::core::replay_report
