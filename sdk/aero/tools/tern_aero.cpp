// tern-aero: the uavbook aircraft model (tern_aero) on the command line (`tern aero ...` runs it).
//
//   tern-aero eval --aircraft FILE --state JSON --delta JSON [--wind JSON]
//       Air data, propeller, body forces and moments, and the 13-state derivative at one state.
//       state: {"p_n","p_e","p_d","u","v","w", "phi","theta","psi" | "e0","e1","e2","e3", "p","q","r"}
//       delta: {"delta_e","delta_a","delta_r","delta_t"}; wind: {"w_n","w_e","w_d","u_g","v_g","w_g"}
//       (steady NED and gust body parts). Missing keys are 0; unknown keys are errors.
//   tern-aero trim --aircraft FILE --Va V [--gamma G] [--radius R] [--altitude H] [--json FILE]
//       Trim state and inputs (Beard & McLain, ch. 5); R in m (> 0 right turn; omit: straight).
//       A table (degrees, percent throttle) then the JSON (radians, throttle 0..1).
//   tern-aero import (--vspaero FILE.stab [--polar FILE.polar] [--aoa DEG] [--controls E A R]
//                     | --xflr5 LOG [--xflr5-control C] [--xflr5-controls-from C=LOG ...])
//                    (--mass KG --inertia Jx Jy Jz Jxz | --mass-file FILE) --out AIRCRAFT.yaml
//       A tern aircraft file from VSPAERO (.stab/.polar) or XFLR5 (type 7 analysis log)
//       stability derivatives; prints how the file was read (the VSPAERO operating point: the one
//       nearest zero angle of attack unless --aoa) and every coefficient the tool did not give,
//       with the value used and why.
//   tern-aero linearize --aircraft FILE --Va V [--gamma G] [--radius R] [--json FILE]
//       Beard & McLain ch. 5 linear models (A_lon, B_lon, A_lat, B_lat), transfer-function
//       coefficients about the trim, and the dynamic modes (short period, phugoid, roll, spiral,
//       dutch roll; modes.hpp) with their textbook approximations.
//   tern-aero gains --aircraft FILE --Va V [--out gains.yaml] [design options]
//       Beard & McLain ch. 6 successive-loop-closure gains for control_slc.
// Output: JSON on stdout (eval; trim and linearize after '#' table lines), text for import and gains. Errors: one line on stderr, exit
// status 1.
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "tern/aircraft.hpp"
#include "tern/aero/model.hpp"
#include "tern/aero/trim.hpp"

#include "tern/aero/pipeline.hpp"
#include "tern/math.hpp"

using json = nlohmann::ordered_json;
namespace sim = tern::sim;

namespace {

// Parses a JSON object of numbers with the allowed keys; "what" names it in errors.
std::map<std::string, double> parse_object(const std::string& text, const std::string& what, const std::set<std::string>& allowed) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    throw std::runtime_error("--" + what + ": not valid JSON (" + std::string(e.what()) + ")");
  }
  if (!j.is_object()) throw std::runtime_error("--" + what + ": expected a JSON object");
  std::map<std::string, double> out;
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (!allowed.count(it.key())) throw std::runtime_error("--" + what + ": unknown key '" + it.key() + "'");
    if (!it.value().is_number()) throw std::runtime_error("--" + what + "." + it.key() + ": expected a number");
    const double v = it.value().get<double>();
    if (!std::isfinite(v)) throw std::runtime_error("--" + what + "." + it.key() + ": value is not finite");
    out[it.key()] = v;
  }
  return out;
}

double get(const std::map<std::string, double>& m, const char* k, double def = 0.0) {
  const auto it = m.find(k);
  return it == m.end() ? def : it->second;
}

std::string fixed(double v, int digits) {
  std::ostringstream o;
  o << std::fixed << std::setprecision(digits) << v;
  return o.str();
}

// s padded with spaces to `width` (right-aligned if `right`).
std::string pad(const std::string& s, std::size_t width, bool right = false) {
  if (s.size() >= width) return s;
  const std::string fill(width - s.size(), ' ');
  return right ? fill + s : s + fill;
}

// Writes j to `path` (nothing if empty).
void write_json(const std::string& path, const json& j) {
  if (path.empty()) return;
  std::ofstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot write");
  f << j.dump(2) << "\n";
  if (!f) throw std::runtime_error(path + ": write failed");
}

json vec(const Eigen::Vector3d& v, const char* a, const char* b, const char* c) {
  json j;
  j[a] = v.x();
  j[b] = v.y();
  j[c] = v.z();
  return j;
}

json state_json(const sim::StateVector& x) {
  static const char* kNames[13] = {"p_n", "p_e", "p_d", "u", "v", "w", "e0", "e1", "e2", "e3", "p", "q", "r"};
  json j;
  for (int i = 0; i < 13; ++i) j[kNames[i]] = x[i];
  return j;
}

int eval(const std::string& file, const std::string& state_s, const std::string& delta_s, const std::string& wind_s) {
  const tern::Aircraft ac = tern::load_aircraft(file);
  const auto st =
      parse_object(state_s, "state", {"p_n", "p_e", "p_d", "u", "v", "w", "phi", "theta", "psi", "e0", "e1", "e2", "e3", "p", "q", "r"});
  const bool euler = st.count("phi") || st.count("theta") || st.count("psi");
  const bool quat = st.count("e0") || st.count("e1") || st.count("e2") || st.count("e3");
  if (euler && quat) throw std::runtime_error("--state: give either phi/theta/psi or e0..e3, not both");
  sim::StateVector x = sim::make_state({get(st, "p_n"), get(st, "p_e"), get(st, "p_d")}, {get(st, "u"), get(st, "v"), get(st, "w")},
                                       get(st, "phi"), get(st, "theta"), get(st, "psi"), {get(st, "p"), get(st, "q"), get(st, "r")});
  if (quat) {
    Eigen::Vector4d e(get(st, "e0"), get(st, "e1"), get(st, "e2"), get(st, "e3"));
    if (e.norm() < 1e-9) throw std::runtime_error("--state: quaternion e0..e3 is zero");
    x.segment<4>(sim::E0) = e.normalized();
  }
  const auto dl = parse_object(delta_s, "delta", {"delta_e", "delta_a", "delta_r", "delta_t"});
  sim::Deltas d;
  d.delta_e = get(dl, "delta_e");
  d.delta_a = get(dl, "delta_a");
  d.delta_r = get(dl, "delta_r");
  d.delta_t = get(dl, "delta_t");
  sim::Wind w;
  if (!wind_s.empty()) {
    const auto wm = parse_object(wind_s, "wind", {"w_n", "w_e", "w_d", "u_g", "v_g", "w_g"});
    w.steady_ned = Eigen::Vector3d(get(wm, "w_n"), get(wm, "w_e"), get(wm, "w_d"));
    w.gust_body = Eigen::Vector3d(get(wm, "u_g"), get(wm, "v_g"), get(wm, "w_g"));
  }
  sim::ForcesMoments fm;
  const sim::StateVector dx = sim::derivative(ac, x, d, w, &fm);
  json out;
  out["aircraft"] = ac.name;
  out["Va"] = fm.air.Va;
  out["alpha"] = fm.air.alpha;
  out["beta"] = fm.air.beta;
  out["Omega"] = fm.prop.Omega;
  out["T_p"] = fm.prop.T_p;
  out["Q_p"] = fm.prop.Q_p;
  out["forces"] = vec(fm.force, "f_x", "f_y", "f_z");
  out["moments"] = vec(fm.moment, "l", "m", "n");
  out["forces_aero"] = vec(fm.f_aero, "f_x", "f_y", "f_z");
  out["forces_gravity"] = vec(fm.f_gravity, "f_x", "f_y", "f_z");
  out["forces_ground"] = vec(fm.f_ground, "f_x", "f_y", "f_z");
  out["state"] = state_json(x);
  json dj;
  static const char* kDot[13] = {"p_n_dot", "p_e_dot", "p_d_dot", "u_dot", "v_dot", "w_dot", "e0_dot",
                                 "e1_dot",  "e2_dot",  "e3_dot",  "p_dot", "q_dot", "r_dot"};
  for (int i = 0; i < 13; ++i) dj[kDot[i]] = dx[i];
  out["derivative"] = dj;
  std::cout << out.dump(2) << "\n";
  return 0;
}

// The trim as a readable table ('#' lines, degrees and percent throttle).
void print_trim_table(std::ostream& os, const std::string& name, double Va, double gamma, double R, const sim::TrimResult& t) {
  os << "# trim of the " << name << " (Beard & McLain ch. 5)\n";
  os << "#   " << pad("Va", 9) << pad(fixed(Va, 3), 10, true) << " m/s\n";
  os << "#   " << pad("gamma", 9) << pad(fixed(gamma * tern::kDegPerRad, 3), 10, true) << " deg\n";
  os << "#   " << pad("R", 9) << pad(std::isinf(R) ? std::string("straight") : fixed(R, 1), 10, true)
     << (std::isinf(R) ? ""
         : R > 0       ? " m (right turn)"
                       : " m (left turn)")
     << "\n";
  const std::pair<const char*, double> deg[] = {{"alpha", t.alpha},
                                                {"beta", t.beta},
                                                {"phi", t.phi},
                                                {"theta", t.theta},
                                                {"delta_e", t.delta.delta_e},
                                                {"delta_a", t.delta.delta_a},
                                                {"delta_r", t.delta.delta_r}};
  for (const auto& [k, v] : deg) os << "#   " << pad(k, 9) << pad(fixed(v * tern::kDegPerRad, 3), 10, true) << " deg\n";
  os << "#   " << pad("delta_t", 9) << pad(fixed(100.0 * t.delta.delta_t, 2), 10, true) << " %\n";
  os << "#   (residual " << t.residual << " after " << t.iterations << " Newton iterations; JSON below in rad)\n";
}

int trim(const std::string& file, double Va, double gamma, double R, double altitude, const std::string& json_out) {
  const tern::Aircraft ac = tern::load_aircraft(file);
  sim::TrimRequest req;
  req.Va = Va;
  req.gamma = gamma;
  req.R = R;
  req.altitude = altitude;
  const sim::TrimResult t = sim::compute_trim(ac, req);
  json out;
  out["aircraft"] = ac.name;
  out["Va"] = Va;
  out["gamma"] = gamma;
  if (std::isinf(R))
    out["R"] = nullptr;
  else
    out["R"] = R;
  out["alpha"] = t.alpha;
  out["beta"] = t.beta;
  out["phi"] = t.phi;
  out["theta"] = t.theta;
  out["delta"] =
      json{{"delta_e", t.delta.delta_e}, {"delta_a", t.delta.delta_a}, {"delta_r", t.delta.delta_r}, {"delta_t", t.delta.delta_t}};
  out["state"] = state_json(t.x);
  out["residual"] = t.residual;
  out["iterations"] = t.iterations;
  write_json(json_out, out);
  print_trim_table(std::cout, ac.name, Va, gamma, R, t);
  std::cout << out.dump(2) << "\n";
  return 0;
}

json matrix(const Eigen::MatrixXd& m) {
  json rows = json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    json r = json::array();
    for (Eigen::Index j = 0; j < m.cols(); ++j) r.push_back(m(i, j));
    rows.push_back(r);
  }
  return rows;
}

std::string file_stem(const std::string& path) {
  std::string s = path.substr(path.find_last_of('/') == std::string::npos ? 0 : path.find_last_of('/') + 1);
  const auto dot = s.find('.');
  return dot == std::string::npos ? s : s.substr(0, dot);
}

struct ImportArgs {
  std::string vspaero, polar, xflr5, mass_file, out, name, propulsion;
  double mass = 0;
  std::vector<double> inertia;
  std::vector<std::string> controls;                      // VSPAERO: elevator aileron rudder groups (empty: automatic)
  double aoa = std::numeric_limits<double>::quiet_NaN();  // VSPAERO operating point, deg
  std::string xflr5_control;                              // what the XFLR5 polar's control variable moves
  std::vector<std::string> xflr5_controls_from;           // CONTROL=FILE: control derivatives from other logs
};

int import_cmd(const ImportArgs& a) {
  if (a.vspaero.empty() == a.xflr5.empty()) throw std::runtime_error("import: give exactly one of --vspaero or --xflr5");
  if (!a.polar.empty() && a.vspaero.empty()) throw std::runtime_error("import: --polar goes with --vspaero");
  tern::aero::MassProperties m;
  if (!a.mass_file.empty()) {
    if (a.mass > 0 || !a.inertia.empty()) throw std::runtime_error("import: give --mass-file or --mass/--inertia, not both");
    m = tern::aero::load_mass_file(a.mass_file);
  } else {
    if (a.mass == 0 || a.inertia.size() != 4)
      throw std::runtime_error("import: give --mass KG and --inertia Jx Jy Jz Jxz (kg m^2), or --mass-file FILE");
    if (!(a.mass > 0) || !std::isfinite(a.mass)) throw std::runtime_error("import: --mass: expected kg > 0, got " + std::to_string(a.mass));
    m = {a.mass, a.inertia[0], a.inertia[1], a.inertia[2], a.inertia[3]};
  }
  if (a.vspaero.empty() && (!a.controls.empty() || !std::isnan(a.aoa)))
    throw std::runtime_error("import: --controls and --aoa go with --vspaero");
  if (a.xflr5.empty() && (!a.xflr5_control.empty() || !a.xflr5_controls_from.empty()))
    throw std::runtime_error("import: --xflr5-control and --xflr5-controls-from go with --xflr5");
  tern::aero::ToolDerivatives t;
  if (!a.vspaero.empty()) {
    tern::aero::VspaeroOptions o;
    o.controls = a.controls;
    o.aoa_deg = a.aoa;
    t = tern::aero::parse_vspaero_stab(a.vspaero, o);
  } else {
    t = tern::aero::parse_xflr5(a.xflr5, a.xflr5_control);
    for (const auto& cf : a.xflr5_controls_from) {  // CONTROL=FILE: one stability polar per control
      const auto eq = cf.find('=');
      if (eq == std::string::npos) throw std::runtime_error("import: --xflr5-controls-from: expected CONTROL=FILE, got '" + cf + "'");
      const std::string control = cf.substr(0, eq), file = cf.substr(eq + 1);
      if (control == "none" || control.empty()) throw std::runtime_error("import: --xflr5-controls-from: name the control in '" + cf + "'");
      const auto c = tern::aero::parse_xflr5(file, control);
      int n = 0;
      for (const auto& [k, v] : c.d)
        if (k.find("_delta_") != std::string::npos) t.d[k] = v, ++n;
      t.notes.push_back(std::to_string(n) + " " + control + " derivatives from " + file + " (its trim alpha " +
                        std::to_string(c.alpha_ref) + " rad)");
    }
  }
  tern::aero::PolarFit pf;
  if (!a.polar.empty()) pf = tern::aero::parse_vspaero_polar(a.polar, t.b * t.b / t.S);
  const std::string name = a.name.empty() ? file_stem(a.out) : a.name;
  const auto r = tern::aero::build_aircraft(t, m, a.polar.empty() ? nullptr : &pf, name, a.propulsion);
  std::vector<std::string> header = {name + ": tern aircraft file written by `tern aero import` from " + t.tool + " output " + t.source,
                                     std::string("(derivatives per radian, ") +
                                         (t.moments_in_stability_axes ? "lateral ones rotated from stability to body axes"
                                                                      : "lateral moments in body axes as the tool writes them") +
                                         ", alpha_ref = " + std::to_string(t.alpha_ref) + " rad).",
                                     "Not given by " + t.tool + " (value used and why):"};
  std::cout << "tern aero import: " << t.tool << " " << t.source << " -> " << a.out << "\n";
  std::cout << "  reference S = " << t.S << " m^2, b = " << t.b << " m, c = " << t.c << " m, alpha_ref = " << t.alpha_ref << " rad ("
            << t.alpha_ref * tern::kDegPerRad << " deg)\n";
  for (const auto& n : t.notes) std::cout << "  " << n << "\n";
  if (!a.polar.empty()) {
    std::cout << "  drag from " << a.polar << " (" << pf.rows << " rows): C_D_p = " << pf.C_D_p << ", e = " << pf.e << "\n";
    for (const auto& n : pf.notes) std::cout << "  " << n << "\n";
  }
  std::cout << "  not provided by " << t.tool << " (value used, why):\n";
  for (const auto& d : r.defaults) {
    std::ostringstream line;
    if (std::isnan(d.value))
      line << d.name << ": " << d.why;
    else
      line << d.name << " = " << d.value << "  (" << d.why << ")";
    std::cout << "    " << line.str() << "\n";
    header.push_back("  " + line.str());
  }
  std::ofstream f(a.out);
  if (!f) throw std::runtime_error(a.out + ": cannot write");
  f << tern::aero::aircraft_yaml(r.aircraft, header);
  if (!f) throw std::runtime_error(a.out + ": write failed");
  f.close();
  tern::load_aircraft(a.out);  // the file must load as sim_aero reads it
  return 0;
}

json or_null(double v, bool has) { return has ? json(v) : json(nullptr); }

// The modes as JSON: name, eigenvalue, and the figures that apply (null otherwise).
json modes_json(const tern::aero::Modes& modes) {
  json out = json::object();
  const std::pair<const char*, const std::vector<tern::aero::Mode>*> groups[] = {{"longitudinal", &modes.lon}, {"lateral", &modes.lat}};
  for (const auto& [group, list] : groups) {
    json arr = json::array();
    for (const auto& m : *list)
      arr.push_back(json{{"name", m.name},
                         {"eigenvalue", json{{"re", m.lambda.real()}, {"im", m.lambda.imag()}}},
                         {"oscillatory", m.oscillatory},
                         {"stable", m.stable},
                         {"wn", m.wn},
                         {"zeta", or_null(m.zeta, m.oscillatory)},
                         {"period", or_null(m.period, m.oscillatory)},
                         {"time_constant", or_null(m.tau, m.tau > 0)},
                         {"time_to_double", or_null(m.t_double, m.t_double > 0)}});
    out[group] = arr;
  }
  out["notes"] = modes.notes;
  return out;
}

json approx_json(const tern::aero::ModeApproximations& a) {
  return json{{"short_period", json{{"wn", a.short_period_wn}, {"zeta", a.short_period_zeta}}},
              {"phugoid", json{{"wn", a.phugoid_wn}, {"zeta", a.phugoid_zeta}}},
              {"roll", json{{"eigenvalue", a.roll_lambda}}},
              {"spiral", json{{"eigenvalue", a.spiral_lambda}}},
              {"dutch_roll", json{{"wn", a.dutch_roll_wn}, {"zeta", a.dutch_roll_zeta}}}};
}

int linearize_cmd(const std::string& file, double Va, double gamma, double R, const std::string& json_out) {
  const tern::Aircraft ac = tern::load_aircraft(file);
  sim::TrimRequest req;
  req.Va = Va;
  req.gamma = gamma;
  req.R = R;
  const tern::aero::LinearModel lm = tern::aero::linearize(ac, req);
  json out;
  out["aircraft"] = ac.name;
  out["Va"] = Va;
  out["gamma"] = gamma;
  if (std::isinf(R))
    out["R"] = nullptr;
  else
    out["R"] = R;
  out["trim"] = json{{"alpha", lm.trim.alpha},           {"theta", lm.trim.theta},           {"phi", lm.trim.phi},
                     {"delta_e", lm.trim.delta.delta_e}, {"delta_a", lm.trim.delta.delta_a}, {"delta_r", lm.trim.delta.delta_r},
                     {"delta_t", lm.trim.delta.delta_t}};
  out["x_lon"] = {"u", "w", "q", "theta", "h"};
  out["u_lon"] = {"delta_e", "delta_t"};
  out["A_lon"] = matrix(lm.A_lon);
  out["B_lon"] = matrix(lm.B_lon);
  out["x_lat"] = {"v", "p", "r", "phi", "psi"};
  out["u_lat"] = {"delta_a", "delta_r"};
  out["A_lat"] = matrix(lm.A_lat);
  out["B_lat"] = matrix(lm.B_lat);
  json tf;
  for (const char* k : {"a_phi1", "a_phi2", "a_theta1", "a_theta2", "a_theta3", "a_V1", "a_V2", "a_V3", "a_beta1", "a_beta2"})
    tf[k] = lm.tf.at(k);
  out["transfer_functions"] = tf;
  const tern::aero::Modes modes = tern::aero::dynamic_modes(lm);
  const tern::aero::ModeApproximations approx = tern::aero::approximate_modes(ac, lm);
  out["modes"] = modes_json(modes);
  out["mode_approximations"] = approx_json(approx);
  write_json(json_out, out);
  // human-readable on stdout, JSON after it
  std::cout << std::fixed << std::setprecision(4);
  std::cout << "# " << ac.name << " at Va = " << Va << " m/s: alpha = " << lm.trim.alpha << " rad, delta_e = " << lm.trim.delta.delta_e
            << " rad, delta_t = " << lm.trim.delta.delta_t << "\n";
  const Eigen::IOFormat fmt(4, 0, "  ", "\n", "#   [", "]");
  std::cout << "# A_lon (x = u w q theta h)\n"
            << lm.A_lon.format(fmt) << "\n# B_lon (delta_e delta_t)\n"
            << lm.B_lon.format(fmt) << "\n# A_lat (x = v p r phi psi)\n"
            << lm.A_lat.format(fmt) << "\n# B_lat (delta_a delta_r)\n"
            << lm.B_lat.format(fmt) << "\n";
  for (auto it = tf.begin(); it != tf.end(); ++it) std::cout << "#   " << it.key() << " = " << it.value().get<double>() << "\n";
  std::cout.unsetf(std::ios::floatfield);
  std::cout << tern::aero::modes_table(modes, approx);
  std::cout << out.dump(2) << "\n";
  return 0;
}

int gains_cmd(const std::string& file, double Va, const tern::aero::DesignOptions& o, const std::string& out_file) {
  const tern::Aircraft ac = tern::load_aircraft(file);
  sim::TrimRequest req;
  req.Va = Va;
  const tern::aero::LinearModel lm = tern::aero::linearize(ac, req);
  const auto g = tern::aero::design_gains(lm, o);
  std::ostringstream s;
  s << "# control_slc gains for the " << ac.name << " at Va = " << Va << " m/s (flat 'param: value'; load with\n"
    << "# param_file:). Written by `tern aero gains --aircraft " << file << " --Va " << Va << "`: uavbook ch. 6\n"
    << "# successive loop closure from the ch. 5 transfer-function coefficients at the trim\n"
    << std::fixed << std::setprecision(4) << "#   trim: alpha = " << lm.trim.alpha << " rad, delta_e = " << lm.trim.delta.delta_e
    << " rad, delta_t = " << lm.trim.delta.delta_t << "\n";
  for (const char* k : {"a_phi1", "a_phi2", "a_theta1", "a_theta2", "a_theta3", "a_V1", "a_V2", "a_V3", "a_beta1", "a_beta2"})
    s << "#   " << k << " = " << lm.tf.at(k) << "\n";
  for (const auto& line : tern::aero::design_summary(lm, o, g)) s << "#   " << line << "\n";
  s << "# limits and takeoff values: control_slc's defaults (set them by hand for a new airframe)\n";
  s.unsetf(std::ios::floatfield);
  s << std::setprecision(6);
  for (const auto& [k, v] : g) s << k << ": " << v << "\n";
  std::cout << s.str();
  if (!out_file.empty()) {
    std::ofstream f(out_file);
    if (!f) throw std::runtime_error(out_file + ": cannot write");
    f << s.str();
    if (!f) throw std::runtime_error(out_file + ": write failed");
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tern aero: the uavbook aircraft model (Beard & McLain) on the command line"};
  app.require_subcommand(1);
  std::string file, state_s, delta_s, wind_s;
  double Va = 0, gamma = 0, R = std::numeric_limits<double>::infinity(), altitude = 100.0;

  auto* ev = app.add_subcommand("eval", "forces, moments and the state derivative at one state");
  ev->add_option("--aircraft", file, "aircraft file (tern or ROSflight format)")->required();
  ev->add_option("--state", state_s, "state as JSON, e.g. '{\"u\": 17, \"p_d\": -100}'")->required();
  ev->add_option("--delta", delta_s, "inputs as JSON, e.g. '{\"delta_e\": 0.1, \"delta_t\": 0.5}'")->required();
  ev->add_option("--wind", wind_s, "wind as JSON: steady w_n w_e w_d, gust u_g v_g w_g (m/s)");

  auto* tr = app.add_subcommand("trim", "trim state and inputs for Va, gamma and turn radius");
  tr->add_option("--aircraft", file, "aircraft file (tern or ROSflight format)")->required();
  tr->add_option("--Va", Va, "airspeed, m/s")->required();
  tr->add_option("--gamma", gamma, "flight-path angle, rad (default 0)");
  tr->add_option("--radius", R, "turn radius, m (> 0 right, < 0 left; default: straight)");
  tr->add_option("--altitude", altitude, "height of the trim state, m (default 100)");
  std::string trim_json;
  tr->add_option("--json", trim_json, "also write the JSON to this file");

  auto* im = app.add_subcommand("import", "a tern aircraft file from VSPAERO (.stab, .polar) or XFLR5 output");
  ImportArgs ia;
  im->add_option("--vspaero", ia.vspaero, "VSPAERO stability file (.stab)");
  im->add_option("--polar", ia.polar, "VSPAERO polar file (.polar): parasitic drag and Oswald factor");
  im->add_option("--xflr5", ia.xflr5, "XFLR5 stability-analysis text output");
  im->add_option("--mass", ia.mass, "mass, kg");
  im->add_option("--inertia", ia.inertia, "Jx Jy Jz Jxz, kg m^2")->expected(4);
  im->add_option("--mass-file", ia.mass_file, "YAML with mass: and inertia: {Jx, Jy, Jz, Jxz} (a tern aircraft file works)");
  im->add_option("--propulsion", ia.propulsion, "tern aircraft file to copy propulsion, servos and stall data from");
  im->add_option("--controls", ia.controls,
                 "VSPAERO control groups for elevator aileron rudder: group names of the case list, ConGrp_<n>, "
                 "'none'; a leading '-' flips the sign (default: found by name, elev*/ail*/rud*)")
      ->expected(3);
  im->add_option("--aoa", ia.aoa,
                 "VSPAERO operating point to read: AoA_ in deg (default: the one nearest zero angle of attack at Beta_ = 0)");
  im->add_option("--xflr5-control", ia.xflr5_control, "what the XFLR5 polar's control variable moves: elevator, aileron, rudder or none");
  im->add_option("--xflr5-controls-from", ia.xflr5_controls_from,
                 "CONTROL=FILE: control derivatives from another XFLR5 log (one stability polar per control)");
  im->add_option("--name", ia.name, "aircraft name (default: the output file's stem)");
  im->add_option("--out", ia.out, "aircraft file to write")->required();

  auto* li = app.add_subcommand("linearize", "uavbook ch. 5 linear models and transfer functions about a trim");
  std::string json_out;
  li->add_option("--aircraft", file, "aircraft file (tern or ROSflight format)")->required();
  li->add_option("--Va", Va, "airspeed, m/s")->required();
  li->add_option("--gamma", gamma, "flight-path angle, rad (default 0)");
  li->add_option("--radius", R, "turn radius, m (> 0 right, < 0 left; default: straight)");
  li->add_option("--json", json_out, "also write the JSON to this file");

  auto* ga = app.add_subcommand("gains", "uavbook ch. 6 successive-loop-closure gains for control_slc");
  tern::aero::DesignOptions o;
  std::string gains_out;
  ga->add_option("--aircraft", file, "aircraft file (tern or ROSflight format)")->required();
  ga->add_option("--Va", Va, "design airspeed, m/s")->required();
  ga->add_option("--out", gains_out, "gains file to write (flat param: value)");
  ga->add_option("--wn-phi", o.wn_phi, "roll natural frequency, rad/s (default a_phi1/(2 zeta_phi))");
  ga->add_option("--zeta-phi", o.zeta_phi, "roll damping ratio (0.8)");
  ga->add_option("--W-chi", o.W_chi, "roll/course bandwidth separation (10)");
  ga->add_option("--T-chi", o.T_chi, "course integrator reset time, s (25)");
  ga->add_option("--K-theta-DC", o.K_theta_DC, "pitch loop DC gain (0.7)");
  ga->add_option("--pitch-ki-ratio", o.pitch_ki_ratio, "pitch_ki = ratio pitch_kp wn_theta (0.1)");
  ga->add_option("--zeta-theta", o.zeta_theta, "pitch damping ratio (0.8)");
  ga->add_option("--W-h", o.W_h, "altitude/pitch bandwidth separation (25)");
  ga->add_option("--zeta-h", o.zeta_h, "altitude damping ratio (1.0)");
  ga->add_option("--wn-V", o.wn_V, "airspeed natural frequency, rad/s (1.5)");
  ga->add_option("--zeta-V", o.zeta_V, "airspeed damping ratio (1.0)");
  ga->add_option("--kr", o.kr, "yaw damper gain, rad per rad/s (0.3)");
  ga->add_option("--p-wo", o.p_wo, "washout pole, rad/s (0.5)");
  ga->add_option("--roll-rate-max", o.roll_rate_max, "slew limit of the roll command, rad/s (1.5; about 0.4 a_phi2 max_a / a_phi1)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (ev->parsed()) return eval(file, state_s, delta_s, wind_s);
    if (im->parsed()) return import_cmd(ia);
    if (li->parsed()) return linearize_cmd(file, Va, gamma, R, json_out);
    if (ga->parsed()) return gains_cmd(file, Va, o, gains_out);
    return trim(file, Va, gamma, R, altitude, trim_json);
  } catch (const std::exception& e) {
    std::cerr << "tern aero: " << e.what() << "\n";
    return 1;
  }
}
