// aero_pipeline.cpp: see aero_pipeline.hpp.
#include "aero_pipeline.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <iomanip>
#include <set>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "tern_sim_aero/model.hpp"

namespace tern::aero {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

[[noreturn]] void fail(const std::string& file, const std::string& field, const std::string& what) {
  throw std::runtime_error(file + ": " + field + ": " + what);
}

std::vector<std::string> read_lines(const std::string& path) {
  std::ifstream f(path);
  if (!f) fail(path, "file", "cannot open");
  std::vector<std::string> lines;
  std::string l;
  while (std::getline(f, l)) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    lines.push_back(l);
  }
  return lines;
}

std::vector<std::string> tokens(const std::string& s) {
  std::istringstream is(s);
  std::vector<std::string> t;
  std::string w;
  while (is >> w) t.push_back(w);
  return t;
}

bool to_double(const std::string& s, double& v) {
  try {
    std::size_t n = 0;
    v = std::stod(s, &n);
    return n == s.size() && std::isfinite(v);
  } catch (const std::exception&) {
    return false;
  }
}

double number(const std::string& file, const std::string& field, const std::string& s) {
  double v = 0;
  if (!to_double(s, v)) fail(file, field, "'" + s + "' is not a finite number");
  return v;
}

// Rotation of lateral quantities from stability to body axes (Beard & McLain sec. 2.2 / 4.2):
// [p_s; r_s] = T [p; r] with T = [c s; -s c]; moments [l; n]_body = T^T [l; n]_stab.
Eigen::Matrix2d stab_T(double alpha) {
  const double c = std::cos(alpha), s = std::sin(alpha);
  Eigen::Matrix2d T;
  T << c, s, -s, c;
  return T;
}

}  // namespace

// ------------------------------------------------------------------------------------ VSPAERO

ToolDerivatives parse_vspaero_stab(const std::string& path, const std::vector<std::string>& controls) {
  if (controls.size() != 3) fail(path, "controls", "expected three control-group names (elevator, aileron, rudder)");
  const auto lines = read_lines(path);
  ToolDerivatives t;
  t.tool = "VSPAERO";
  t.source = path;
  t.rates_in_stability_axes = false;  // VSPAERO perturbs the body rates p, q, r
  std::map<std::string, double> header;
  std::vector<std::string> cols;     // column names after "Coef"
  std::vector<double> col_scale;     // per deg -> per rad
  std::map<std::string, std::vector<double>> rows;
  static const std::set<std::string> kRows = {"CFx", "CFy", "CFz", "CMx", "CMy", "CMz",
                                              "CL", "CD", "CS", "CMl", "CMm", "CMn"};
  for (std::size_t i = 0; i < lines.size(); ++i) {
    auto tk = tokens(lines[i]);
    if (tk.empty()) continue;
    if (tk[0] == "#" && tk.size() > 2 && tk[1] == "Coef") {  // column names, then the unit row
      cols.assign(tk.begin() + 2, tk.end());
      if (i + 1 >= lines.size()) fail(path, "derivative table", "no unit row after the column names");
      auto u = tokens(lines[i + 1]);
      // "#  -  per rad  per rad ... per M  per u ..."
      std::vector<std::string> units;
      for (std::size_t k = 1; k < u.size(); ++k) {
        if (u[k] == "per" && k + 1 < u.size()) {
          units.push_back(u[k + 1]);
          ++k;
        } else {
          units.push_back(u[k]);
        }
      }
      if (units.size() != cols.size()) fail(path, "derivative table", "unit row does not match the column names");
      for (const auto& un : units) col_scale.push_back(un == "deg" ? 1.0 / kDeg : 1.0);
      ++i;
      continue;
    }
    if (tk[0].size() > 1 && tk[0].back() == '_' && tk.size() >= 2) {  // "Sref_  0.52  Lunit^2"
      double v = 0;
      if (to_double(tk[1], v)) header[tk[0]] = v;
      continue;
    }
    if (kRows.count(tk[0]) && !cols.empty()) {
      if (tk.size() != cols.size() + 1) fail(path, tk[0], "expected " + std::to_string(cols.size()) + " values");
      std::vector<double> v;
      for (std::size_t k = 1; k < tk.size(); ++k) v.push_back(number(path, tk[0], tk[k]) * col_scale[k - 1]);
      rows[tk[0]] = v;
    }
  }
  if (cols.empty()) fail(path, "derivative table", "no '# Coef Total Alpha ...' header found (not a VSPAERO .stab file?)");
  for (const char* k : {"Sref_", "Cref_", "Bref_", "AoA_"}) {
    if (!header.count(k)) fail(path, k, "missing");
  }
  t.S = header["Sref_"];
  t.c = header["Cref_"];
  t.b = header["Bref_"];
  t.alpha_ref = header["AoA_"] * kDeg;
  if (header.count("Rho_")) t.rho = header["Rho_"];
  auto col = [&](const std::string& name) -> int {
    for (std::size_t k = 0; k < cols.size(); ++k)
      if (cols[k] == name) return static_cast<int>(k);
    return -1;
  };
  auto get = [&](const char* row, const std::string& c, const char* tern) {
    const int k = col(c);
    if (k < 0 || !rows.count(row)) return;
    t.d[tern] = rows[row][static_cast<std::size_t>(k)];
  };
  // longitudinal: wind-axis rows (CL, CD, CMm); lateral: CFy (body y) and CMl, CMn (stability
  // axes at beta = 0).
  get("CL", "Total", "C_L");
  get("CD", "Total", "C_D");
  get("CMm", "Total", "C_m");
  get("CL", "Alpha", "C_L_alpha");
  get("CL", "q", "C_L_q");
  get("CL", controls[0], "C_L_delta_e");
  get("CD", "Alpha", "C_D_alpha");
  get("CD", "q", "C_D_q");
  get("CD", controls[0], "C_D_delta_e");
  get("CMm", "Alpha", "C_m_alpha");
  get("CMm", "q", "C_m_q");
  get("CMm", controls[0], "C_m_delta_e");
  const std::pair<const char*, const char*> lat[] = {{"CFy", "C_Y"}, {"CMl", "C_ell"}, {"CMn", "C_n"}};
  for (const auto& [row, base] : lat) {
    const std::string b = base;
    get(row, "Beta", (b + "_beta").c_str());
    get(row, "p", (b + "_p").c_str());
    get(row, "r", (b + "_r").c_str());
    get(row, controls[1], (b + "_delta_a").c_str());
    get(row, controls[2], (b + "_delta_r").c_str());
  }
  if (!t.d.count("C_L_alpha")) fail(path, "CL wrt Alpha", "missing");
  return t;
}

PolarFit parse_vspaero_polar(const std::string& path, double AR) {
  const auto lines = read_lines(path);
  std::vector<std::string> cols;
  PolarFit f;
  double sum_cdo = 0, s_xy = 0, s_xx = 0;
  for (const auto& l : lines) {
    auto tk = tokens(l);
    if (tk.empty()) continue;
    if (cols.empty()) {
      if (tk[0] == "Beta") cols = tk;
      continue;
    }
    if (tk.size() != cols.size()) fail(path, "row '" + l + "'", "expected " + std::to_string(cols.size()) + " columns");
    std::map<std::string, double> r;
    for (std::size_t k = 0; k < tk.size(); ++k) r[cols[k]] = number(path, cols[k], tk[k]);
    for (const char* k : {"CL", "CDo", "CDi"})
      if (!r.count(k)) fail(path, k, "column missing");
    sum_cdo += r["CDo"];
    const double x = r["CL"] * r["CL"] / (kPi * AR);
    s_xy += x * r["CDi"];
    s_xx += x * x;
    ++f.rows;
  }
  if (f.rows == 0) fail(path, "table", "no 'Beta Mach AoA ... CL CDo CDi ...' rows found (not a VSPAERO .polar?)");
  f.C_D_p = sum_cdo / f.rows;
  if (!(s_xx > 0) || !(s_xy > 0)) fail(path, "CDi", "cannot fit an Oswald factor (CL all zero or CDi <= 0)");
  f.e = s_xx / s_xy;  // CDi = CL^2/(pi e AR): least squares of 1/e
  return f;
}

// -------------------------------------------------------------------------------------- XFLR5

ToolDerivatives parse_xflr5(const std::string& path) {
  const auto lines = read_lines(path);
  ToolDerivatives t;
  t.tool = "XFLR5";
  t.source = path;
  t.rates_in_stability_axes = true;
  static const std::map<std::string, std::string> kNames = {
      {"CLa", "C_L_alpha"}, {"CLq", "C_L_q"}, {"Cma", "C_m_alpha"}, {"Cmq", "C_m_q"},
      {"CYb", "C_Y_beta"}, {"CYp", "C_Y_p"}, {"CYr", "C_Y_r"},
      {"Clb", "C_ell_beta"}, {"Clp", "C_ell_p"}, {"Clr", "C_ell_r"},
      {"Cnb", "C_n_beta"}, {"Cnp", "C_n_p"}, {"Cnr", "C_n_r"},
      {"CLde", "C_L_delta_e"}, {"CDde", "C_D_delta_e"}, {"Cmde", "C_m_delta_e"},
      {"CYda", "C_Y_delta_a"}, {"Clda", "C_ell_delta_a"}, {"Cnda", "C_n_delta_a"},
      {"CYdr", "C_Y_delta_r"}, {"Cldr", "C_ell_delta_r"}, {"Cndr", "C_n_delta_r"},
      {"CL", "C_L"}, {"CD", "C_D"}, {"Cm", "C_m"}, {"Cxa", "C_X_alpha"}};
  bool have_alpha = false;
  for (const auto& l0 : lines) {
    const std::string& l = l0;
    std::string low = l;
    for (auto& ch : low) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    const auto eq = l.find('=');
    if (eq == std::string::npos) continue;
    // reference lines: "Ref. area  = 0.52 m2", "Ref. span = 2.08 m", "Ref. chord = 0.235 m"
    auto ref = [&](const char* word, double& out) {
      const auto w = low.find(word);
      if (w == std::string::npos || w > eq) return false;
      auto tk = tokens(l.substr(eq + 1));
      if (tk.empty()) fail(path, word, "no value");
      out = number(path, word, tk[0]);
      return true;
    };
    const bool is_ref = low.find("ref") < eq || low.find("mean") < eq || low.find("wing") < eq;
    if (is_ref && (ref("area", t.S) || ref("span", t.b) || ref("chord", t.c))) continue;
    std::string spaced;  // "Name= value" pairs: a name is the token before '='
    for (char ch : l0) {
      if (ch == '=') spaced += " = ";
      else spaced += ch;
    }
    auto tk = tokens(spaced);
    for (std::size_t k = 0; k + 2 < tk.size(); ++k) {
      if (tk[k + 1] != "=") continue;
      const std::string& key = tk[k];
      if (key == "Density") {
        t.rho = number(path, key, tk[k + 2]);
      } else if (key == "Alpha") {
        t.alpha_ref = number(path, key, tk[k + 2]) * kDeg;
        have_alpha = true;
      } else if (auto it = kNames.find(key); it != kNames.end()) {
        t.d[it->second] = number(path, key, tk[k + 2]);
      }
    }
  }
  if (!t.d.count("C_L_alpha")) fail(path, "CLa", "missing (not an XFLR5 stability-analysis output?)");
  // stability axes held fixed: C_X = -C_D + C_L dalpha, so C_D_alpha = C_L - C_X_alpha
  if (t.d.count("C_X_alpha") && t.d.count("C_L")) t.d["C_D_alpha"] = t.d["C_L"] - t.d["C_X_alpha"];
  if (!have_alpha) fail(path, "Alpha", "missing (the operating point's angle of attack)");
  return t;
}

MassProperties load_mass_file(const std::string& path) {
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    fail(path, "file", e.what());
  }
  MassProperties m;
  auto rd = [&](const YAML::Node& n, const std::string& field) {
    if (!n) fail(path, field, "missing required field");
    double v = 0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(path, field, "expected a number");
    }
    if (!std::isfinite(v)) fail(path, field, "value is not finite");
    return v;
  };
  m.mass = rd(doc["mass"], "mass");
  const YAML::Node J = doc["inertia"];
  if (!J || !J.IsMap()) fail(path, "inertia", "missing required section {Jx, Jy, Jz, Jxz}");
  m.Jx = rd(J["Jx"], "inertia.Jx");
  m.Jy = rd(J["Jy"], "inertia.Jy");
  m.Jz = rd(J["Jz"], "inertia.Jz");
  m.Jxz = rd(J["Jxz"], "inertia.Jxz");
  return m;
}

// ---------------------------------------------------------------------------------- aircraft

ImportResult build_aircraft(const ToolDerivatives& t, const MassProperties& m, const PolarFit* polar,
                            const std::string& name, const std::string& propulsion_from) {
  ImportResult r;
  sim::Aircraft& ac = r.aircraft;
  ac.name = name;
  ac.source = t.source;
  ac.mass = m.mass;
  ac.Jx = m.Jx;
  ac.Jy = m.Jy;
  ac.Jz = m.Jz;
  ac.Jxz = m.Jxz;
  if (!(t.S > 0)) fail(t.source, "reference area", "missing or not positive");
  if (!(t.b > 0)) fail(t.source, "reference span", "missing or not positive");
  if (!(t.c > 0)) fail(t.source, "reference chord", "missing or not positive");
  ac.S = t.S;
  ac.b = t.b;
  ac.c = t.c;
  auto& D = r.defaults;
  const std::string by = "not given by " + t.tool;

  // environment, stall and propulsion: not aerodynamic-analysis outputs
  ac.rho = t.rho > 0 ? t.rho : 1.225;
  if (!(t.rho > 0)) D.push_back({"environment.rho", ac.rho, by + ": ISA sea level"});
  if (!propulsion_from.empty()) {
    const sim::Aircraft p = sim::load_aircraft(propulsion_from);
    ac.prop = p.prop;
    ac.servo_tau = p.servo_tau;
    ac.max_delta_a = p.max_delta_a;
    ac.max_delta_e = p.max_delta_e;
    ac.max_delta_r = p.max_delta_r;
    ac.M = p.M;
    ac.alpha0 = p.alpha0;
    ac.stall_blend = p.stall_blend;
    ac.gear = p.gear;
    D.push_back({"propulsion.*, servos.*, gear.*, wing.M, wing.alpha0, wing.stall_blend",
                 std::numeric_limits<double>::quiet_NaN(),
                 "copied from " + propulsion_from});
  } else {
    auto& p = ac.prop;  // the Anaconda's (ROSflight anaconda_dynamics.yaml): 15 in prop, 560 KV, 6S
    p.D_prop = 0.381;
    p.C_T_0 = 0.06288743;
    p.C_T_1 = -0.02704452;
    p.C_T_2 = -0.31320732;
    p.C_Q_0 = 0.00614891;
    p.C_Q_1 = -0.0106795;
    p.C_Q_2 = -0.011779;
    p.K_V = 560.0;
    p.K_Q = 0.01705;
    p.R_motor = 0.042;
    p.i0 = 1.5;
    p.V_max = 24.0;
    ac.servo_tau = 0.01;
    ac.max_delta_a = ac.max_delta_e = ac.max_delta_r = 0.6981317;
    ac.M = 50.0;
    ac.alpha0 = 0.4712;
    ac.stall_blend = false;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    D.push_back({"propulsion.*", nan,
                 "typical: the Anaconda's motor and propeller (ROSflight; give --propulsion FILE for yours)"});
    D.push_back({"servos.*", nan, "typical: 40-degree limits, tau 0.01 s (the Anaconda's)"});
    D.push_back({"wing.M", ac.M, "typical: the book's blending rate"});
    D.push_back({"wing.alpha0", ac.alpha0, "typical: the book's stall angle (27 deg)"});
    D.push_back({"wing.stall_blend", 0.0, "false: linear lift (as ROSflight); the VLM gives no stall"});
    ac.gear.points = sim::default_gear_points(ac.b);
    D.push_back({"gear.*", std::numeric_limits<double>::quiet_NaN(), "sim_aero's default tricycle scaled by the span"});
  }

  // lateral: stability -> body axes
  auto val = [&](const std::string& k, double& out, const char* why_zero) {
    auto it = t.d.find(k);
    if (it != t.d.end()) return (out = it->second), true;
    out = 0.0;
    D.push_back({"aero." + k, 0.0, by + ": " + why_zero});
    return false;
  };
  auto& a = ac.aero;
  const Eigen::Matrix2d T = stab_T(t.alpha_ref);
  double lb = 0, nb = 0, lp = 0, lr = 0, np = 0, nr = 0, lda = 0, nda = 0, ldr = 0, ndr = 0, yp = 0, yr = 0;
  val("C_ell_beta", lb, "zero");
  val("C_n_beta", nb, "zero");
  val("C_ell_p", lp, "zero");
  val("C_ell_r", lr, "zero");
  val("C_n_p", np, "zero");
  val("C_n_r", nr, "zero");
  val("C_ell_delta_a", lda, "zero (no aileron control group)");
  val("C_n_delta_a", nda, "zero (no aileron control group)");
  val("C_ell_delta_r", ldr, "zero (no rudder control group)");
  val("C_n_delta_r", ndr, "zero (no rudder control group)");
  val("C_Y_p", yp, "zero");
  val("C_Y_r", yr, "zero");
  val("C_Y_beta", a.C_Y_beta, "zero");
  val("C_Y_delta_a", a.C_Y_delta_a, "zero");
  val("C_Y_delta_r", a.C_Y_delta_r, "zero");
  const Eigen::Vector2d beta_b = T.transpose() * Eigen::Vector2d(lb, nb);
  const Eigen::Vector2d da_b = T.transpose() * Eigen::Vector2d(lda, nda);
  const Eigen::Vector2d dr_b = T.transpose() * Eigen::Vector2d(ldr, ndr);
  Eigen::Matrix2d Dr;
  Dr << lp, lr, np, nr;
  Eigen::RowVector2d Yr(yp, yr);
  if (t.rates_in_stability_axes) {
    Dr = (T.transpose() * Dr * T).eval();
    Yr = (Yr * T).eval();
  } else {
    Dr = (T.transpose() * Dr).eval();
  }
  a.C_ell_beta = beta_b(0);
  a.C_n_beta = beta_b(1);
  a.C_ell_delta_a = da_b(0);
  a.C_n_delta_a = da_b(1);
  a.C_ell_delta_r = dr_b(0);
  a.C_n_delta_r = dr_b(1);
  a.C_ell_p = Dr(0, 0);
  a.C_ell_r = Dr(0, 1);
  a.C_n_p = Dr(1, 0);
  a.C_n_r = Dr(1, 1);
  a.C_Y_p = Yr(0);
  a.C_Y_r = Yr(1);
  a.C_Y_0 = a.C_ell_0 = a.C_n_0 = 0.0;
  D.push_back({"aero.C_Y_0, C_ell_0, C_n_0", 0.0, "zero: symmetric aircraft"});

  // longitudinal (lift, drag and pitch are the same in stability and body-pitch terms)
  val("C_L_alpha", a.C_L_alpha, "zero");
  val("C_L_q", a.C_L_q, "zero");
  val("C_L_delta_e", a.C_L_delta_e, "zero (no elevator control group)");
  val("C_m_alpha", a.C_m_alpha, "zero");
  val("C_m_q", a.C_m_q, "zero");
  val("C_m_delta_e", a.C_m_delta_e, "zero (no elevator control group)");
  val("C_D_q", a.C_D_q, "zero (negligible; the book's value)");
  val("C_D_delta_e", a.C_D_delta_e, "zero");
  double CL = 0, Cm = 0, CD = 0;
  if (val("C_L", CL, "zero lift at alpha_ref")) a.C_L_0 = CL - a.C_L_alpha * t.alpha_ref;
  else a.C_L_0 = -a.C_L_alpha * t.alpha_ref;
  if (val("C_m", Cm, "zero pitching moment at alpha_ref")) a.C_m_0 = Cm - a.C_m_alpha * t.alpha_ref;
  else a.C_m_0 = -a.C_m_alpha * t.alpha_ref;
  const bool have_CD = val("C_D", CD, "zero drag at alpha_ref");
  val("C_D_alpha", a.C_D_alpha, "zero");
  a.C_D_0 = CD - a.C_D_alpha * t.alpha_ref;
  if (polar != nullptr) {
    a.C_D_p = polar->C_D_p;
    ac.e = polar->e;
  } else {
    ac.e = 0.9;
    D.push_back({"wing.e", ac.e, "no .polar: typical Oswald efficiency"});
    const double cdp = have_CD ? CD - CL * CL / (kPi * ac.e * ac.AR()) : 0.0;
    if (cdp > 0.005) {
      a.C_D_p = cdp;
      D.push_back({"aero.C_D_p", cdp, "no .polar: C_D - C_L^2/(pi e AR) at alpha_ref"});
    } else {
      a.C_D_p = 0.03;
      D.push_back({"aero.C_D_p", 0.03, "no .polar and no viscous drag in the analysis: typical small UAV"});
    }
  }
  sim::validate(ac);
  return r;
}

std::string aircraft_yaml(const sim::Aircraft& ac, const std::vector<std::string>& header) {
  std::ostringstream o;
  o << std::setprecision(10);
  for (const auto& h : header) o << "# " << h << "\n";
  const auto& a = ac.aero;
  const auto& p = ac.prop;
  o << "name: " << ac.name << "\nmass: " << ac.mass << "\ninertia:\n  Jx: " << ac.Jx << "\n  Jy: " << ac.Jy
    << "\n  Jz: " << ac.Jz << "\n  Jxz: " << ac.Jxz << "\nenvironment:\n  rho: " << ac.rho << "\nwing:\n  S: " << ac.S
    << "\n  b: " << ac.b << "\n  c: " << ac.c << "\n  e: " << ac.e << "\n  M: " << ac.M << "\n  alpha0: " << ac.alpha0
    << "\n  stall_blend: " << (ac.stall_blend ? "true" : "false") << "\naero:\n";
  const std::pair<const char*, double> co[] = {
      {"C_L_0", a.C_L_0}, {"C_L_alpha", a.C_L_alpha}, {"C_L_q", a.C_L_q}, {"C_L_delta_e", a.C_L_delta_e},
      {"C_D_p", a.C_D_p}, {"C_D_q", a.C_D_q}, {"C_D_delta_e", a.C_D_delta_e}, {"C_D_0", a.C_D_0},
      {"C_D_alpha", a.C_D_alpha}, {"C_m_0", a.C_m_0}, {"C_m_alpha", a.C_m_alpha}, {"C_m_q", a.C_m_q},
      {"C_m_delta_e", a.C_m_delta_e}, {"C_Y_0", a.C_Y_0}, {"C_Y_beta", a.C_Y_beta}, {"C_Y_p", a.C_Y_p},
      {"C_Y_r", a.C_Y_r}, {"C_Y_delta_a", a.C_Y_delta_a}, {"C_Y_delta_r", a.C_Y_delta_r},
      {"C_ell_0", a.C_ell_0}, {"C_ell_beta", a.C_ell_beta}, {"C_ell_p", a.C_ell_p}, {"C_ell_r", a.C_ell_r},
      {"C_ell_delta_a", a.C_ell_delta_a}, {"C_ell_delta_r", a.C_ell_delta_r}, {"C_n_0", a.C_n_0},
      {"C_n_beta", a.C_n_beta}, {"C_n_p", a.C_n_p}, {"C_n_r", a.C_n_r}, {"C_n_delta_a", a.C_n_delta_a},
      {"C_n_delta_r", a.C_n_delta_r}};
  for (const auto& [k, v] : co) o << "  " << k << ": " << v << "\n";
  o << "propulsion:\n  D_prop: " << p.D_prop << "\n  C_T_0: " << p.C_T_0 << "\n  C_T_1: " << p.C_T_1
    << "\n  C_T_2: " << p.C_T_2 << "\n  C_Q_0: " << p.C_Q_0 << "\n  C_Q_1: " << p.C_Q_1 << "\n  C_Q_2: " << p.C_Q_2
    << "\n  K_Q: " << p.K_Q << "\n  R_motor: " << p.R_motor << "\n  i0: " << p.i0 << "\n  V_max: " << p.V_max
    << "\nservos:\n  tau: " << ac.servo_tau << "\n  max_delta_a: " << ac.max_delta_a
    << "\n  max_delta_e: " << ac.max_delta_e << "\n  max_delta_r: " << ac.max_delta_r << "\n";
  return o.str();
}

// --------------------------------------------------------------------------------- linearize

LinearModel linearize(const sim::Aircraft& ac, const sim::TrimRequest& req) {
  LinearModel lm;
  lm.Va = req.Va;
  lm.trim = sim::compute_trim(ac, req);
  const sim::TrimResult& tr = lm.trim;
  const sim::StateVector& xs = tr.x;
  const double phi0 = tr.phi, theta0 = tr.theta, psi0 = req.psi, h0 = -xs[sim::PD];
  const sim::Wind calm;
  // full reduced state z = [u v w p q r phi theta psi h], inputs [de da dr dt]
  using Z = Eigen::Matrix<double, 10, 1>;
  using In = Eigen::Vector4d;
  Z z0;
  z0 << xs[sim::U], xs[sim::V], xs[sim::W], xs[sim::P], xs[sim::Q], xs[sim::R], phi0, theta0, psi0, h0;
  const In in0(tr.delta.delta_e, tr.delta.delta_a, tr.delta.delta_r, tr.delta.delta_t);
  auto f = [&](const Z& z, const In& in) {
    const sim::StateVector x = sim::make_state({0, 0, -z[9]}, {z[0], z[1], z[2]}, z[6], z[7], z[8], {z[3], z[4], z[5]});
    sim::Deltas d;
    d.delta_e = in[0];
    d.delta_a = in[1];
    d.delta_r = in[2];
    d.delta_t = in[3];
    const sim::StateVector dx = sim::derivative(ac, x, d, calm);
    const double sp = std::sin(z[6]), cp = std::cos(z[6]), tt = std::tan(z[7]), ct = std::cos(z[7]);
    Z dz;
    dz << dx[sim::U], dx[sim::V], dx[sim::W], dx[sim::P], dx[sim::Q], dx[sim::R],
        z[3] + z[4] * sp * tt + z[5] * cp * tt,  // book eq. 3.3
        z[4] * cp - z[5] * sp, (z[4] * sp + z[5] * cp) / ct, -dx[sim::PD];
    return dz;
  };
  Eigen::Matrix<double, 10, 10> A;
  Eigen::Matrix<double, 10, 4> B;
  for (int j = 0; j < 10; ++j) {
    const double h = 1e-5 * std::max(1.0, std::abs(z0[j]));
    Z zp = z0, zm = z0;
    zp[j] += h;
    zm[j] -= h;
    A.col(j) = (f(zp, in0) - f(zm, in0)) / (2 * h);
  }
  for (int j = 0; j < 4; ++j) {
    const double h = 1e-6;
    In ip = in0, im = in0;
    ip[j] += h;
    im[j] -= h;
    B.col(j) = (f(z0, ip) - f(z0, im)) / (2 * h);
  }
  const int lon[5] = {0, 2, 4, 7, 9}, lat[5] = {1, 3, 5, 6, 8};
  const int ulon[2] = {0, 3}, ulat[2] = {1, 2};
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      lm.A_lon(i, j) = A(lon[i], lon[j]);
      lm.A_lat(i, j) = A(lat[i], lat[j]);
    }
    for (int j = 0; j < 2; ++j) {
      lm.B_lon(i, j) = B(lon[i], ulon[j]);
      lm.B_lat(i, j) = B(lat[i], ulat[j]);
    }
  }
  // transfer-function coefficients (book sec. 5.4, a_V1/a_V2 with the propeller model)
  const auto& a = ac.aero;
  const double Va = req.Va, rho = ac.rho, S = ac.S, b = ac.b, c = ac.c, m = ac.mass;
  const double Gam = ac.Jx * ac.Jz - ac.Jxz * ac.Jxz;
  const double G3 = ac.Jz / Gam, G4 = ac.Jxz / Gam;
  const double Cpp = G3 * a.C_ell_p + G4 * a.C_n_p;
  const double Cpda = G3 * a.C_ell_delta_a + G4 * a.C_n_delta_a;
  auto& k = lm.tf;
  k["a_phi1"] = -0.5 * rho * Va * Va * S * b * Cpp * b / (2 * Va);
  k["a_phi2"] = 0.5 * rho * Va * Va * S * b * Cpda;
  const double qc = rho * Va * Va * c * S / (2 * ac.Jy);
  k["a_theta1"] = -qc * a.C_m_q * c / (2 * Va);
  k["a_theta2"] = -qc * a.C_m_alpha;
  k["a_theta3"] = qc * a.C_m_delta_e;
  const double dt = tr.delta.delta_t, hv = 1e-4;
  const double dT_dVa = (sim::propulsion(ac, Va + hv, dt).T_p - sim::propulsion(ac, Va - hv, dt).T_p) / (2 * hv);
  const double dT_ddt = (sim::propulsion(ac, Va, dt + hv).T_p - sim::propulsion(ac, Va, dt - hv).T_p) / (2 * hv);
  k["a_V1"] = rho * Va * S / m * (sim::drag_coefficient(ac, tr.alpha) + a.C_D_delta_e * tr.delta.delta_e) - dT_dVa / m;
  k["a_V2"] = dT_ddt / m;
  k["a_V3"] = sim::kG * std::cos(tr.theta - tr.alpha);
  k["a_beta1"] = -rho * Va * S / (2 * m) * a.C_Y_beta;
  k["a_beta2"] = rho * Va * S / (2 * m) * a.C_Y_delta_r;
  return lm;
}

// ------------------------------------------------------------------------------------- gains

std::vector<std::pair<std::string, double>> design_gains(const LinearModel& lm, const DesignOptions& o) {
  const auto& k = lm.tf;
  const double Va = lm.Va, g = sim::kG;
  std::vector<std::pair<std::string, double>> out;
  // roll (sec. 6.1.1): closed loop s^2 + (a_phi1 + a_phi2 kd) s + a_phi2 kp
  const double wn_phi = std::isnan(o.wn_phi) ? k.at("a_phi1") / (2 * o.zeta_phi) : o.wn_phi;
  const double roll_kp = wn_phi * wn_phi / k.at("a_phi2");
  const double roll_kd = std::max(0.0, (2 * o.zeta_phi * wn_phi - k.at("a_phi1")) / k.at("a_phi2"));
  out.push_back({"roll_kp", roll_kp});
  out.push_back({"roll_kd", roll_kd});
  out.push_back({"roll_ki", 0.0});
  // course (sec. 6.1.2): P bandwidth wn_phi / W_chi, slow integrator T_chi
  const double wc = std::sqrt(k.at("a_phi2") * roll_kp) / o.W_chi;
  const double course_kp = wc * Va / g;
  out.push_back({"course_kp", course_kp});
  out.push_back({"course_ki", course_kp / o.T_chi});
  out.push_back({"course_kd", 0.0});
  // pitch (sec. 6.2.1); tern's pitch gains are magnitudes (the book's are negative)
  const double a1 = k.at("a_theta1"), a2 = k.at("a_theta2"), a3 = k.at("a_theta3");
  const double kp_th = o.K_theta_DC * a2 / ((1 - o.K_theta_DC) * a3);
  const double wn_th = std::sqrt(a2 + kp_th * a3);
  const double kd_th = (2 * o.zeta_theta * wn_th - a1) / a3;
  const double K_dc = kp_th * a3 / (a2 + kp_th * a3);
  out.push_back({"pitch_kp", -kp_th});
  out.push_back({"pitch_kd", std::max(0.0, -kd_th)});
  out.push_back({"pitch_ki", o.pitch_ki_ratio * (-kp_th) * wn_th});
  // altitude from pitch (sec. 6.2.2, eq. 6.24)
  const double wn_h = wn_th / o.W_h;
  out.push_back({"altitude_ki", wn_h * wn_h / (K_dc * Va)});
  out.push_back({"altitude_kp", 2 * o.zeta_h * wn_h / (K_dc * Va)});
  out.push_back({"altitude_kd", 0.0});
  // airspeed with throttle (sec. 6.2.4, eq. 6.29)
  out.push_back({"airspeed_ki", o.wn_V * o.wn_V / k.at("a_V2")});
  out.push_back({"airspeed_kp", std::max(0.0, (2 * o.zeta_V * o.wn_V - k.at("a_V1")) / k.at("a_V2"))});
  out.push_back({"airspeed_kd", 0.0});
  // yaw damper (sec. 6.1.3)
  out.push_back({"yaw_damper_kr", o.kr});
  out.push_back({"yaw_damper_p_wo", o.p_wo});
  out.push_back({"trim_e", lm.trim.delta.delta_e});
  out.push_back({"trim_t", lm.trim.delta.delta_t});
  return out;
}

}  // namespace tern::aero
