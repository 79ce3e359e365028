// The replay report as text (the table `tern replay` prints) and as JSON (replay_report.json).
#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "config/error.hpp"
#include "replay/replay_report.hpp"

namespace tern::core {

namespace {

using nlohmann::json;

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json figure_json(const ErrorFigure& f, const ReplayWindow& w) {
  return {{"rms", number(f.rms)}, {"max", number(f.max)}, {"mean", number(f.mean)}, {"unit", f.unit},
          {"samples", f.samples}, {"rule", f.rule},       {"window", w.rule}};
}

json nis_json(const NisStats& s) {
  return {{"count", s.count},
          {"rejected", s.rejected},
          {"share_rejected", number(s.share_rejected)},
          {"mean_nis", number(s.mean_nis)},
          {"p50_nis", number(s.p50_nis)},
          {"p95_nis", number(s.p95_nis)},
          {"p99_nis", number(s.p99_nis)},
          {"p50_ratio", number(s.p50_ratio)},
          {"p95_ratio", number(s.p95_ratio)},
          {"p99_ratio", number(s.p99_ratio)}};
}

json measurements_json(const ReplayReport& r) {
  if (r.measurements.empty()) return {{"status", r.measurements_absent.empty() ? "absent (no columns)" : r.measurements_absent}};
  json out = json::object();
  out["rule"] =
      "innovations.csv: per message with a fused sample, the largest test ratio since the previous message; NIS = ratio * gate; "
      "rejected: ratio > 1; percentiles linear between order statistics; whole: the whole replay, window: " +
      r.window.rule;
  for (const auto& m : r.measurements) out[m.name] = {{"gate", m.gate}, {"whole", nis_json(m.whole)}, {"window", nis_json(m.window)}};
  return out;
}

json estimator_json(const EstimatorCounters& c) {
  if (c.instance.empty()) return {{"status", "absent (summary.json names no estimator with counters)"}};
  json models = json::object();
  for (const auto& m : c.models)
    models[m.model] = {{"accepted", m.accepted}, {"rejected", number(m.rejected)}, {"mean_nis", number(m.mean_nis)}};
  json resets = json::object();
  for (const auto& [k, v] : c.resets) resets[k] = v;
  return {{"instance", c.instance},
          {"rule", "summary.json instances." + c.instance + ": the whole replay"},
          {"models", models},
          {"resets", resets}};
}

json rows_json(const RowAccount& a) {
  if (!a.absent.empty()) return {{"status", a.absent}};
  json topics = json::object();
  for (const auto& t : a.topics)
    topics[t.topic] = {{"rows", t.rows},       {"played", t.played}, {"received", t.received},
                       {"invalid", t.invalid}, {"missed", t.missed}, {"lost", t.lost()}};
  return {{"rule",
           "summary.json: the replay instance's <topic>_rows and _played against the estimator's <sensor>_received (fused, gated, "
           "used to initialise or calibrate, or invalid), _invalid and <input>_missed (its queue could not hold them); lost = played - "
           "received; rows after the tick of the last IMU row are not played"},
          {"lost", a.lost},
          {"not_played", a.not_played},
          {"topics", topics}};
}

json validity_json(const Validity& v) {
  return {{"first_valid_s", number(v.first_valid_s)},
          {"share_valid", number(v.share_valid)},
          {"samples", v.samples},
          {"rule",
           "state.csv valid == 1, share of the samples from the first valid one; divergences: valid -> invalid transitions "
           "after it plus summary.json's filter_resets"},
          {"valid_to_invalid", v.valid_to_invalid},
          {"filter_resets", v.filter_resets},
          {"divergences", v.divergences},
          {"nan_cells", v.nan_cells},
          {"nan_rows", v.nan_rows}};
}

json reference_json(const ReplayReport& r) {
  const auto& c = r.reference;
  if (!c.absent.empty()) return {{"status", c.absent}};
  const auto& w = r.window;
  return {{"status", "compared"},
          {"roll", figure_json(c.roll, w)},
          {"pitch", figure_json(c.pitch, w)},
          {"yaw", figure_json(c.yaw, w)},
          {"course", figure_json(c.course, w)},
          {"position_horizontal", figure_json(c.position_h, w)},
          {"position_vertical", figure_json(c.position_v, w)},
          {"velocity_horizontal", figure_json(c.velocity_h, w)},
          {"velocity_vertical", figure_json(c.velocity_v, w)}};
}

json gnss_json(const ReplayReport& r) {
  const auto& g = r.gnss;
  if (!g.absent.empty()) return {{"status", g.absent}};
  const auto& w = r.window;
  return {
      {"status", "compared"},
      {"time_of_validity", g.time_rule},
      {"fixes", g.fixes},
      {"fixes_in_window", g.fixes_in_window},
      {"position_horizontal", figure_json(g.position_h, w)},
      {"velocity_horizontal", figure_json(g.velocity_h, w)},
      {"course", figure_json(g.course, w)},
      {"share_pos_accepted", number(g.share_pos_accepted)},
      {"share_vel_accepted", number(g.share_vel_accepted)},
      {"share_accepted_rule", "the estimator's counters (summary.json gnss_pos/gnss_vel accepted / (accepted + rejected)), whole replay"}};
}

json wind_json(const ReplayReport& r) {
  const auto& d = r.wind;
  if (!d.absent.empty()) return {{"status", d.absent}};
  return {{"status", "estimated"},
          {"mean_speed", number(d.mean_speed)},
          {"max_speed", number(d.max_speed)},
          {"unit", "m/s"},
          {"samples", d.samples},
          {"rule", "|(w_n, w_e)| of the valid state samples in the window"},
          {"window", r.window.rule},
          {"vs_reference", figure_json(d.vs_reference, r.window)}};
}

json specific_force_json(const ReplayReport& r) {
  const auto& c = r.specific_force;
  if (!c.absent.empty()) return {{"status", c.absent}};
  return {{"status", "checked"},
          {"epochs", c.epochs},
          {"accelerated_epochs", c.accelerated},
          {"pitch", figure_json(c.pitch, r.window)},
          {"roll", figure_json(c.roll, r.window)},
          {"reference_pitch", figure_json(c.reference_pitch, r.window)},
          {"reference_roll", figure_json(c.reference_roll, r.window)}};
}

json mag_field_json(const ReplayReport& r) {
  const auto& c = r.mag_field;
  if (!c.absent.empty()) return {{"status", c.absent}};
  return {{"status", "checked"},
          {"rule", c.rule},
          {"window", r.window.rule},
          {"samples", c.samples},
          {"measured",
           {{"intensity_uT", number(c.intensity)},
            {"intensity_p5_uT", number(c.intensity_p5)},
            {"intensity_p95_uT", number(c.intensity_p95)},
            {"horizontal_uT", number(c.horizontal)},
            {"vertical_uT", number(c.vertical)},
            {"inclination_deg", number(c.inclination)}}},
          {"model",
           {{"source", c.model},
            {"intensity_uT", number(c.model_intensity)},
            {"horizontal_uT", number(c.model_horizontal)},
            {"vertical_uT", number(c.model_vertical)},
            {"inclination_deg", number(c.model_inclination)},
            {"years_outside_span", c.years_outside},
            {"forecast_drift_uT_per_year", number(c.drift_intensity)},
            {"forecast_drift_deg_per_year", number(c.drift_inclination)},
            {"forecast_drift_rule", c.drift_rule},
            {"expected_error_uT", number(c.expected_intensity)},
            {"expected_error_deg", number(c.expected_inclination)}}},
          {"heading_sectors", c.sectors},
          {"heading_spread_uT", number(c.heading_spread)}};
}

/// The object at a dotted path ("reference.position_vertical"), or nullptr.
json* object_at(json& j, const std::string& where) {
  json* o = &j;
  std::size_t from = 0;
  while (o != nullptr && from <= where.size()) {
    const std::size_t dot = std::min(where.find('.', from), where.size());
    const std::string key = where.substr(from, dot - from);
    o = o->is_object() && o->contains(key) ? &(*o)[key] : nullptr;
    from = dot + 1;
  }
  return o != nullptr && o->is_object() ? o : nullptr;
}

/// Each explanation as the "note" of the figures it is about, and as "where: text" in "notes".
void add_explanations(json& j, const ReplayReport& r) {
  for (const auto& e : r.explanations) {
    for (const auto& where : e.where)
      if (json* o = object_at(j, where)) (*o)["note"] = o->contains("note") ? (*o)["note"].get<std::string>() + "; " + e.text : e.text;
    j["notes"].push_back((e.where.empty() ? std::string("report") : e.where.front()) + ": " + e.text);
  }
}

}  // namespace

nlohmann::json to_json(const ReplayReport& r) {
  json j;
  j["run_dir"] = r.run_dir.string();
  j["replay"] = {{"start_s", r.replay_start_s}, {"end_s", r.replay_end_s}};
  j["window"] = {{"start_s", r.window.start_s}, {"end_s", r.window.end_s}, {"rule", r.window.rule}};
  j["validity"] = validity_json(r.validity);
  j["measurements"] = measurements_json(r);
  j["estimator"] = estimator_json(r.counters);
  j["rows"] = rows_json(r.rows);
  j["reference"] = reference_json(r);
  j["gnss"] = gnss_json(r);
  j["wind"] = wind_json(r);
  j["specific_force"] = specific_force_json(r);
  j["mag_field"] = mag_field_json(r);
  j["notes"] = r.notes;
  add_explanations(j, r);
  return j;
}

void write_replay_report(const ReplayReport& r) {
  const auto path = r.run_dir / "replay_report.json";
  std::ofstream out(path);
  out << to_json(r).dump(2) << '\n';
  if (!out) throw ConfigError(path.string() + ": cannot write");
}

}  // namespace tern::core
