// aircraft_build.cpp: mass files, the tern aircraft built from a tool's derivatives, and its YAML
// (see tern/aero/import.hpp).
#include "tern/aero/import.hpp"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "aero_text.hpp"
#include "tern/atmosphere.hpp"
#include "tern/input_file.hpp"

namespace tern::aero {
using namespace text;
namespace {

// Rotation of lateral quantities from stability to body axes (Beard & McLain sec. 2.2 / 4.2):
// [p_s; r_s] = T [p; r] with T = [c s; -s c]; moments [l; n]_body = T^T [l; n]_stab.
Eigen::Matrix2d stab_T(double alpha) {
  const double c = std::cos(alpha), s = std::sin(alpha);
  Eigen::Matrix2d T;
  T << c, s, -s, c;
  return T;
}

}  // namespace

MassProperties load_mass_file(const std::string& path) {
  const YAML::Node doc = load_yaml_file(path, "mass file");  // bounded: size, regular file, alias bombs
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

ImportResult build_aircraft(const ToolDerivatives& t, const MassProperties& m, const PolarFit* polar, const std::string& name,
                            const std::string& propulsion_from) {
  ImportResult r;
  tern::Aircraft& ac = r.aircraft;
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
  ac.rho = t.rho > 0 ? t.rho : tern::kIsaSeaLevelDensity;
  if (!(t.rho > 0)) D.push_back({"environment.rho", ac.rho, by + ": ISA sea level"});
  if (!propulsion_from.empty()) {
    const tern::Aircraft p = tern::load_aircraft(propulsion_from);
    ac.prop = p.prop;
    ac.servo_tau = p.servo_tau;
    ac.max_delta_a = p.max_delta_a;
    ac.max_delta_e = p.max_delta_e;
    ac.max_delta_r = p.max_delta_r;
    ac.M = p.M;
    ac.alpha0 = p.alpha0;
    ac.stall_blend = p.stall_blend;
    ac.gear = p.gear;
    D.push_back({"propulsion.*, servos.*, gear.*, wing.M, wing.alpha0, wing.stall_blend", std::numeric_limits<double>::quiet_NaN(),
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
    D.push_back({"propulsion.*", nan, "typical: the Anaconda's motor and propeller (ROSflight; give --propulsion FILE for yours)"});
    D.push_back({"servos.*", nan, "typical: 40-degree limits, tau 0.01 s (the Anaconda's)"});
    D.push_back({"wing.M", ac.M, "typical: the book's blending rate"});
    D.push_back({"wing.alpha0", ac.alpha0, "typical: the book's stall angle (27 deg)"});
    D.push_back({"wing.stall_blend", 0.0, "false: linear lift (as ROSflight); the VLM gives no stall"});
    ac.gear.points = tern::default_gear_points(ac.b);
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
  // moment rows: [l; n]_body = T^T [l; n]_stab (XFLR5); VSPAERO's are body-axis moments already
  const Eigen::Matrix2d Rm = t.moments_in_stability_axes ? Eigen::Matrix2d(T.transpose()) : Eigen::Matrix2d::Identity();
  const Eigen::Vector2d beta_b = Rm * Eigen::Vector2d(lb, nb);
  const Eigen::Vector2d da_b = Rm * Eigen::Vector2d(lda, nda);
  const Eigen::Vector2d dr_b = Rm * Eigen::Vector2d(ldr, ndr);
  Eigen::Matrix2d Dr;
  Dr << lp, lr, np, nr;
  Eigen::RowVector2d Yr(yp, yr);
  if (t.rates_in_stability_axes) {  // rate columns: [p; r]_stab = T [p; r]_body
    Dr = (Rm * Dr * T).eval();
    Yr = (Yr * T).eval();
  } else {
    Dr = (Rm * Dr).eval();
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
  if (val("C_L", CL, "zero lift at alpha_ref"))
    a.C_L_0 = CL - a.C_L_alpha * t.alpha_ref;
  else
    a.C_L_0 = -a.C_L_alpha * t.alpha_ref;
  if (val("C_m", Cm, "zero pitching moment at alpha_ref"))
    a.C_m_0 = Cm - a.C_m_alpha * t.alpha_ref;
  else
    a.C_m_0 = -a.C_m_alpha * t.alpha_ref;
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
  tern::validate_aircraft(ac);
  return r;
}

std::string aircraft_yaml(const tern::Aircraft& ac, const std::vector<std::string>& header) {
  std::ostringstream o;
  o << std::setprecision(10);
  for (const auto& h : header) o << "# " << h << "\n";
  const auto& a = ac.aero;
  const auto& p = ac.prop;
  o << "name: " << ac.name << "\nmass: " << ac.mass << "\ninertia:\n  Jx: " << ac.Jx << "\n  Jy: " << ac.Jy << "\n  Jz: " << ac.Jz
    << "\n  Jxz: " << ac.Jxz << "\nenvironment:\n  rho: " << ac.rho << "\nwing:\n  S: " << ac.S << "\n  b: " << ac.b << "\n  c: " << ac.c
    << "\n  e: " << ac.e << "\n  M: " << ac.M << "\n  alpha0: " << ac.alpha0 << "\n  stall_blend: " << (ac.stall_blend ? "true" : "false")
    << "\naero:\n";
  const std::pair<const char*, double> co[] = {{"C_L_0", a.C_L_0},
                                               {"C_L_alpha", a.C_L_alpha},
                                               {"C_L_q", a.C_L_q},
                                               {"C_L_delta_e", a.C_L_delta_e},
                                               {"C_D_p", a.C_D_p},
                                               {"C_D_q", a.C_D_q},
                                               {"C_D_delta_e", a.C_D_delta_e},
                                               {"C_D_0", a.C_D_0},
                                               {"C_D_alpha", a.C_D_alpha},
                                               {"C_m_0", a.C_m_0},
                                               {"C_m_alpha", a.C_m_alpha},
                                               {"C_m_q", a.C_m_q},
                                               {"C_m_delta_e", a.C_m_delta_e},
                                               {"C_Y_0", a.C_Y_0},
                                               {"C_Y_beta", a.C_Y_beta},
                                               {"C_Y_p", a.C_Y_p},
                                               {"C_Y_r", a.C_Y_r},
                                               {"C_Y_delta_a", a.C_Y_delta_a},
                                               {"C_Y_delta_r", a.C_Y_delta_r},
                                               {"C_ell_0", a.C_ell_0},
                                               {"C_ell_beta", a.C_ell_beta},
                                               {"C_ell_p", a.C_ell_p},
                                               {"C_ell_r", a.C_ell_r},
                                               {"C_ell_delta_a", a.C_ell_delta_a},
                                               {"C_ell_delta_r", a.C_ell_delta_r},
                                               {"C_n_0", a.C_n_0},
                                               {"C_n_beta", a.C_n_beta},
                                               {"C_n_p", a.C_n_p},
                                               {"C_n_r", a.C_n_r},
                                               {"C_n_delta_a", a.C_n_delta_a},
                                               {"C_n_delta_r", a.C_n_delta_r}};
  for (const auto& [k, v] : co) o << "  " << k << ": " << v << "\n";
  o << "propulsion:\n  D_prop: " << p.D_prop << "\n  C_T_0: " << p.C_T_0 << "\n  C_T_1: " << p.C_T_1 << "\n  C_T_2: " << p.C_T_2
    << "\n  C_Q_0: " << p.C_Q_0 << "\n  C_Q_1: " << p.C_Q_1 << "\n  C_Q_2: " << p.C_Q_2 << "\n  K_Q: " << p.K_Q
    << "\n  R_motor: " << p.R_motor << "\n  i0: " << p.i0 << "\n  V_max: " << p.V_max << "\nservos:\n  tau: " << ac.servo_tau
    << "\n  max_delta_a: " << ac.max_delta_a << "\n  max_delta_e: " << ac.max_delta_e << "\n  max_delta_r: " << ac.max_delta_r << "\n";
  return o.str();
}

}  // namespace tern::aero
