// core/apps/sysid/sysid_output.cpp: aircraft.yaml, sysid.json, index.html and the table (sysid_output.hpp).
#include "sysid/sysid_output.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "config/error.hpp"
#include "tern/input_file.hpp"

namespace tern::core::sysid {

namespace {

/// The prior's document with aero.<name> replaced by each estimate (and wing.e by the polar's).
std::string aircraft_yaml(const SysidResult& r, const SysidProvenance& from) {
  YAML::Node doc = load_yaml_file(from.prior, "aircraft file");
  if (!doc["aero"] || !doc["aero"].IsMap())
    throw ConfigError(fmt::format(
        "{}: aero: not a tern aircraft file (a map 'aero' of the uavbook's coefficients); convert it with tern aero import", from.prior));
  for (const auto& c : r.coefficients) doc["aero"][c.name] = c.estimate;
  if (doc["wing"] && doc["wing"].IsMap()) doc["wing"]["e"] = r.aircraft.e;
  // the delays the series was paired with are the servos' (a negative one is the log's stamping, not theirs)
  for (std::size_t i = 0; i < r.command_delay_s.size(); ++i) {
    const std::string key = std::string("delay_") + "aer"[i];
    if (r.command_delay_s[i] > 0.0 || (doc["servos"] && doc["servos"][key])) doc["servos"][key] = std::max(r.command_delay_s[i], 0.0);
  }
  doc["name"] = r.aircraft.name + "-identified";
  YAML::Emitter e;
  e.SetDoublePrecision(6);
  e << doc;
  return fmt::format("# {} identified by tern sysid from {} (prior {}); the estimates and their bounds: sysid.json\n{}\n", r.aircraft.name,
                     from.log, from.prior, e.c_str());
}

/// The field of the loader's message "SOURCE:LINE: FIELD: problem" ("" when it names none).
std::string refused_field(const std::string& message) {
  const auto a = message.find(": ");
  const auto b = a == std::string::npos ? a : message.find(": ", a + 2);
  return b == std::string::npos ? "" : message.substr(a + 2, b - a - 2);
}

}  // namespace

void keep_loadable(SysidResult& r, const SysidProvenance& from) {
  for (std::size_t tries = 0; tries <= r.coefficients.size() + 1; ++tries) {
    std::string why;
    try {
      Aircraft loaded = parse_aircraft(YAML::Load(aircraft_yaml(r, from)), "aircraft.yaml");
      loaded.name = r.aircraft.name;
      r.aircraft = loaded;  // the file as written, the prior's values where an estimate was not adopted
      return;
    } catch (const std::runtime_error& e) {
      why = e.what();
    }
    const std::string field = refused_field(why);
    const std::string problem = why.substr(why.find(field) + field.size() + 2);
    if (field == "wing.e" && r.oswald.identified) {
      r.notes.push_back(fmt::format("e (Oswald factor): not adopted: {} (the aircraft format's); the prior {:.3f} kept", problem,
                                    r.oswald.estimate = load_aircraft(from.prior).e));
      r.oswald.identified = false, r.aircraft.e = r.oswald.estimate;
      continue;
    }
    auto c = std::find_if(r.coefficients.begin(), r.coefficients.end(),
                          [&](const CoefficientEstimate& x) { return field == "aero." + x.name && x.identified; });
    if (c == r.coefficients.end()) throw ConfigError(fmt::format("the identified aircraft does not load: {}", why));
    c->note = fmt::format("not adopted: {} (the aircraft format's)", problem);
    c->estimate = c->prior, c->std_error = 0.0, c->identified = false;
    r.notes.push_back(fmt::format("{}: {}; the prior {:.4g} kept", c->name, c->note, c->prior));
  }
}

namespace {

/// "0.0116 +- 0.0030 (26 %, the pitot scale's bound alone 0.0025)" (without the pitot's part where
/// the scale has no bound), or "0.0022 (the prior's polar)" where no bound was found.
std::string drag_at_trim_text(const SysidResult& r) {
  if (!std::isfinite(r.C_D_trim_std_error)) return fmt::format("{:.4f} (the prior's polar)", r.C_D_trim);
  const std::string pitot =
      r.trim_drag_bound.pitot_shift > 0.0 ? fmt::format(", the pitot scale's bound alone {:.4f}", r.trim_drag_bound.pitot_shift) : "";
  return fmt::format("{:.4f} +- {:.4f} ({:.0f} %{})", r.C_D_trim, r.C_D_trim_std_error, 100.0 * r.C_D_trim_std_error / std::abs(r.C_D_trim),
                     pitot);
}

nlohmann::json to_json(const SysidResult& r, const SysidProvenance& from) {
  nlohmann::json j;
  j["produced_by"] = {
      {"command", "tern sysid"}, {"log", from.log}, {"prior", from.prior}, {"estimate", from.estimate}, {"options", from.options}};
  j["samples"] = r.samples, j["segments"] = r.segments, j["airborne_s"] = r.airborne_s;
  for (const auto& c : r.coefficients) {
    j["coefficients"][c.name] = {{"estimate", c.estimate},     {"std_error", c.std_error}, {"prior", c.prior},
                                 {"identified", c.identified}, {"method", c.method},       {"note", c.note}};
    if (c.identified)
      j["coefficients"][c.name]["equation_error"] = {{"estimate", c.equation_error}, {"std_error", c.equation_error_std_error}};
  }
  for (const auto& f : r.fits)
    j["fits"].push_back({{"axis", f.axis},
                         {"domain", f.domain},
                         {"r_squared", f.r_squared},
                         {"r_squared_generalized", f.r_squared_generalized},
                         {"rms_residual", f.rms_residual},
                         {"rows", f.rows}});
  j["drag_at_trim"] = {{"prior", r.C_D_trim_prior},
                       {"identified", r.C_D_trim},
                       {"std_error", std::isfinite(r.C_D_trim_std_error) ? nlohmann::json(r.C_D_trim_std_error) : nlohmann::json()},
                       {"std_error_pitot_scale", r.trim_drag_bound.pitot_shift},
                       {"alpha", r.trim_alpha},
                       {"delta_e", r.trim_delta_e},
                       {"change_per_deg_of_alpha", r.C_D_per_deg}};
  j["oswald_e"] = r.aircraft.e;
  const auto nuisance = [](const NuisanceEstimate& e, const char* unit) {
    return nlohmann::json{
        {"estimate", e.estimate}, {"std_error", e.std_error}, {"identified", e.identified}, {"note", e.note}, {"unit", unit}};
  };
  j["oswald"] = nuisance(r.oswald, "");
  j["instrumentation"] = {{"pitot_scale", nuisance(r.pitot_scale, "Va_true / Va_pitot")},
                          {"accel_x_bias", nuisance(r.accel_x_bias, "m/s^2")},
                          {"motor_tau", nuisance(r.motor_tau, "s")},
                          {"wind_ne", {r.wind_n, r.wind_e}}};
  j["command_delay_s"] = {{"aileron", r.command_delay_s[0]}, {"elevator", r.command_delay_s[1]}, {"rudder", r.command_delay_s[2]}};
  j["command_delay_estimate"] = {{"aileron", nuisance(r.delay_shift[0], "s after the starting delay")},
                                 {"elevator", nuisance(r.delay_shift[1], "s after the starting delay")},
                                 {"rudder", nuisance(r.delay_shift[2], "s after the starting delay")}};
  j["notes"] = r.notes;
  return j;
}

/// "command delay: aileron 10 ms, elevator 10 ms, rudder 10 ms (each command paired with the motion ...)".
std::string delay_line(const SysidResult& r) {
  const auto& d = r.command_delay_s;
  return fmt::format(
      "command delay: aileron {:.1f} ms, elevator {:.1f} ms, rudder {:.1f} ms (each command paired with the motion that "
      "long after its stamp: estimated from the flight, or given by --command-delay)",
      1e3 * d[0], 1e3 * d[1], 1e3 * d[2]);
}

/// One SVG panel: measured (black) and predicted (orange) against time.
std::string svg_panel(const AxisSeries& s) {
  if (s.t.empty()) return "";
  const double W = 900, H = 160;
  double lo = *std::min_element(s.measured.begin(), s.measured.end()), hi = *std::max_element(s.measured.begin(), s.measured.end());
  for (const double v : s.predicted) lo = std::min(lo, v), hi = std::max(hi, v);
  if (hi <= lo) hi = lo + 1e-9;
  const double t0 = s.t.front(), t1 = std::max(s.t.back(), t0 + 1e-9);
  auto line = [&](const std::vector<double>& v, const char* colour) {
    std::string pts;
    for (std::size_t k = 0; k < v.size(); ++k)
      pts += fmt::format("{:.1f},{:.1f} ", (s.t[k] - t0) / (t1 - t0) * W, H - (v[k] - lo) / (hi - lo) * H);
    return fmt::format("<polyline fill='none' stroke='{}' stroke-width='1' points='{}'/>", colour, pts);
  };
  return fmt::format(
      "<h3>{} (measured black, identified model orange; {:.4g} .. {:.4g}; t {:.1f} .. {:.1f} s)</h3>\n"
      "<svg width='{}' height='{}' style='border:1px solid #ccc'>{}{}</svg>\n",
      s.axis, lo, hi, t0, t1, W, H, line(s.measured, "black"), line(s.predicted, "#e07000"));
}

std::string html(const SysidResult& r, const SysidProvenance& from) {
  std::string rows;
  for (const auto& c : r.coefficients)
    rows += fmt::format("<tr><td>{}</td><td>{:.5g}</td><td>{:.5g}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n", c.name, c.prior,
                        c.estimate, c.identified ? fmt::format("{:.2g}", c.std_error) : "", c.method,
                        c.method == "output error" ? fmt::format("{:.5g} +- {:.2g}", c.equation_error, c.equation_error_std_error) : "",
                        c.identified ? "identified" : c.note);
  std::string panels;
  for (const auto& s : r.series) panels += svg_panel(s);
  std::string notes;
  for (const auto& n : r.notes) notes += "<li>" + n + "</li>\n";
  notes += "<li>" + delay_line(r) + "</li>\n";
  return fmt::format(
      "<!doctype html><html><head><meta charset='utf-8'><title>tern sysid: {}</title>"
      "<style>body{{font-family:sans-serif}} td,th{{padding:2px 8px;text-align:right}} "
      "td:first-child,td:last-child{{text-align:left}}</style>"
      "</head><body><h1>tern sysid: {}</h1><p>log {}<br>prior {}<br>estimate {}<br>{}</p>"
      "<p>{} airborne samples in {} stretches, {:.0f} s. Drag at trim: prior {:.4f}, identified {}; 1 deg of alpha bias moves it by "
      "{:.0f} %.</p>"
      "<table><tr><th>coefficient</th><th>prior</th><th>estimate</th><th>std error</th><th>method</th><th>equation "
      "error</th><th></th></tr>\n{}</table>"
      "<ul>{}</ul>{}</body></html>\n",
      r.aircraft.name, r.aircraft.name, from.log, from.prior, from.estimate, from.options, r.samples, r.segments, r.airborne_s,
      r.C_D_trim_prior, drag_at_trim_text(r), 100.0 * r.C_D_per_deg, rows, notes, panels);
}

}  // namespace

/// Measured and predicted coefficients over the longest stretch, one row per sample.
std::string series_csv(const SysidResult& r) {
  std::string out = "t [s]";
  for (const auto& s : r.series) out += fmt::format(",{0}_measured [],{0}_predicted []", s.axis);
  out += "\n";
  const std::size_t n = r.series.empty() ? 0 : r.series.front().t.size();
  for (std::size_t k = 0; k < n; ++k) {
    out += fmt::format("{:.4f}", r.series.front().t[k]);
    for (const auto& s : r.series) out += fmt::format(",{:.6g},{:.6g}", s.measured[k], s.predicted[k]);
    out += "\n";
  }
  return out;
}

void write_text_file(const std::filesystem::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out.flush()) throw ConfigError(fmt::format("{}: cannot write", file.string()));
}

void write_sysid_outputs(const SysidResult& r, const SysidProvenance& from, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  write_text_file(dir / "coefficients.csv", series_csv(r));
  write_text_file(dir / "aircraft.yaml", aircraft_yaml(r, from));
  write_text_file(dir / "sysid.json", to_json(r, from).dump(2) + "\n");
  write_text_file(dir / "index.html", html(r, from));
}

std::string format_sysid_table(const SysidResult& r) {
  std::string out = fmt::format("{:<14} {:>10} {:>10} {:>9}  {}\n", "coefficient", "prior", "estimate", "std err", "");
  for (const auto& c : r.coefficients) {
    // a held term whose prior moved with its surface (prior_update.hpp, r.held_scaled)
    const bool moved =
        !c.identified && std::any_of(r.held_scaled.begin(), r.held_scaled.end(), [&](const HeldScaling& h) { return h.held == c.name; });
    out += fmt::format("{:<14} {:>10.4g} {:>10.4g} {:>9}  {}\n", c.name, c.prior, c.estimate,
                       c.identified ? fmt::format("{:.2g}", c.std_error) : "-",
                       c.identified ? c.method : (moved ? "prior scaled: " : "prior kept: ") + c.note);
  }
  out += fmt::format("drag at trim: prior {:.4f}, identified {}; 1 deg of alpha or pitch bias moves it by {:.0f} %\n", r.C_D_trim_prior,
                     drag_at_trim_text(r), 100.0 * r.C_D_per_deg);
  const auto line = [](const NuisanceEstimate& e, const char* fmt_identified) {
    return e.identified ? fmt::format(fmt::runtime(fmt_identified), e.estimate, e.std_error) : "not identifiable (" + e.note + ")";
  };
  const std::string pitot = r.pitot_scale.note.rfind(kStatedPitotScale, 0) == 0
                                ? fmt::format("{:.3f} +- {:.2g} ({})", r.pitot_scale.estimate, r.pitot_scale.std_error, r.pitot_scale.note)
                                : line(r.pitot_scale, "{:.3f} +- {:.2g}");
  out += fmt::format("pitot scale {}, accelerometer x bias {}, motor lag {}\n", pitot, line(r.accel_x_bias, "{:.3f} +- {:.2g} m/s^2"),
                     r.motor_tau.identified ? fmt::format("{:.3f} +- {:.2g} s", r.motor_tau.estimate, r.motor_tau.std_error)
                                            : fmt::format("{:.3f} s ({})", r.motor_tau.estimate, r.motor_tau.note));
  out += delay_line(r) + "\n";
  for (const auto& f : r.fits) {
    // an instrumented fit is judged by its generalized R^2 (regression.hpp): both shown
    const std::string generalized =
        f.r_squared_generalized != f.r_squared ? fmt::format(" (instrumented: generalized R^2 {:.3f})", f.r_squared_generalized) : "";
    out += fmt::format("fit {:<10} {:<4} R^2 {:.3f}{}, rms residual {:.3g}, {} rows\n", f.axis, f.domain, f.r_squared, generalized,
                       f.rms_residual, f.rows);
  }
  return out;
}

}  // namespace tern::core::sysid
