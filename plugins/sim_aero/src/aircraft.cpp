// Aircraft file loader: tern format and ROSflight `*_dynamics.yaml` (see aircraft.hpp).
#include "tern_sim_aero/aircraft.hpp"

#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

namespace tern::sim {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

[[noreturn]] void fail(const std::string& source, const std::string& field, const std::string& what) {
  throw std::runtime_error(source + ": " + field + ": " + what);
}

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

double read_double(const YAML::Node& n, const std::string& source, const std::string& field) {
  if (!n.IsScalar()) fail(source, field, "expected a number");
  double v = 0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(source, field, "expected a number, got '" + n.Scalar() + "'");
  }
  if (!std::isfinite(v)) fail(source, field, "value " + n.Scalar() + " is not finite");
  return v;
}

struct Field {
  const char* key;
  double* dst;
  bool required;
};

// Reads the fields of one map section; unknown keys and missing required keys are errors.
void read_section(const YAML::Node& sec, const std::string& prefix, const std::vector<Field>& fields,
                  const std::string& source, const std::set<std::string>& extra_keys = {}) {
  if (!sec.IsMap()) fail(source, prefix, "expected a map");
  std::set<std::string> seen;
  for (const auto& kv : sec) {
    const std::string key = kv.first.as<std::string>();
    const std::string path = prefix.empty() ? key : prefix + "." + key;
    if (extra_keys.count(key)) continue;
    bool found = false;
    for (const auto& f : fields) {
      if (key == f.key) {
        *f.dst = read_double(kv.second, source, path);
        seen.insert(key);
        found = true;
        break;
      }
    }
    if (!found) fail(source, path, "unknown key");
  }
  for (const auto& f : fields) {
    if (f.required && !seen.count(f.key)) {
      fail(source, prefix.empty() ? f.key : prefix + "." + f.key, "missing required field");
    }
  }
}

Aircraft parse_tern(const YAML::Node& doc, const std::string& source) {
  Aircraft ac;
  ac.source = source;
  static const std::set<std::string> kTop = {"name", "description", "source", "mass", "inertia",
                                             "environment", "wing", "aero", "propulsion",
                                             "servos", "gear"};
  for (const auto& kv : doc) {
    const std::string key = kv.first.as<std::string>();
    if (!kTop.count(key)) fail(source, key, "unknown key");
  }
  auto section = [&](const char* name, bool required) -> YAML::Node {
    YAML::Node n = doc[name];
    if (!n && required) fail(source, name, "missing required section");
    return n;
  };
  if (doc["name"]) ac.name = doc["name"].as<std::string>();
  if (!doc["mass"]) fail(source, "mass", "missing required field");
  ac.mass = read_double(doc["mass"], source, "mass");

  read_section(section("inertia", true), "inertia",
               {{"Jx", &ac.Jx, true}, {"Jy", &ac.Jy, true}, {"Jz", &ac.Jz, true}, {"Jxz", &ac.Jxz, true}},
               source);
  read_section(section("environment", true), "environment", {{"rho", &ac.rho, true}}, source);
  const YAML::Node wing = section("wing", true);
  double blend = 1.0;
  if (wing.IsMap() && wing["stall_blend"]) {
    try {
      blend = wing["stall_blend"].as<bool>() ? 1.0 : 0.0;
    } catch (const YAML::Exception&) {
      fail(source, "wing.stall_blend", "expected true or false");
    }
  }
  ac.stall_blend = blend != 0.0;
  read_section(wing, "wing",
               {{"S", &ac.S, true}, {"b", &ac.b, true}, {"c", &ac.c, true}, {"e", &ac.e, true},
                {"M", &ac.M, true}, {"alpha0", &ac.alpha0, true}},
               source, {"stall_blend"});
  auto& a = ac.aero;
  read_section(section("aero", true), "aero",
               {{"C_L_0", &a.C_L_0, true}, {"C_L_alpha", &a.C_L_alpha, true},
                {"C_L_q", &a.C_L_q, true}, {"C_L_delta_e", &a.C_L_delta_e, true},
                {"C_D_0", &a.C_D_0, false}, {"C_D_alpha", &a.C_D_alpha, false},
                {"C_D_p", &a.C_D_p, true}, {"C_D_q", &a.C_D_q, true},
                {"C_D_delta_e", &a.C_D_delta_e, true},
                {"C_m_0", &a.C_m_0, true}, {"C_m_alpha", &a.C_m_alpha, true},
                {"C_m_q", &a.C_m_q, true}, {"C_m_delta_e", &a.C_m_delta_e, true},
                {"C_Y_0", &a.C_Y_0, true}, {"C_Y_beta", &a.C_Y_beta, true},
                {"C_Y_p", &a.C_Y_p, true}, {"C_Y_r", &a.C_Y_r, true},
                {"C_Y_delta_a", &a.C_Y_delta_a, true}, {"C_Y_delta_r", &a.C_Y_delta_r, true},
                {"C_ell_0", &a.C_ell_0, true}, {"C_ell_beta", &a.C_ell_beta, true},
                {"C_ell_p", &a.C_ell_p, true}, {"C_ell_r", &a.C_ell_r, true},
                {"C_ell_delta_a", &a.C_ell_delta_a, true}, {"C_ell_delta_r", &a.C_ell_delta_r, true},
                {"C_n_0", &a.C_n_0, true}, {"C_n_beta", &a.C_n_beta, true},
                {"C_n_p", &a.C_n_p, true}, {"C_n_r", &a.C_n_r, true},
                {"C_n_delta_a", &a.C_n_delta_a, true}, {"C_n_delta_r", &a.C_n_delta_r, true}},
               source);
  auto& p = ac.prop;
  const YAML::Node prop = section("propulsion", true);
  read_section(prop, "propulsion",
               {{"D_prop", &p.D_prop, true}, {"C_T_0", &p.C_T_0, true}, {"C_T_1", &p.C_T_1, true},
                {"C_T_2", &p.C_T_2, true}, {"C_Q_0", &p.C_Q_0, true}, {"C_Q_1", &p.C_Q_1, true},
                {"C_Q_2", &p.C_Q_2, true}, {"K_V", &p.K_V, false}, {"K_Q", &p.K_Q, false},
                {"R_motor", &p.R_motor, true}, {"i0", &p.i0, true}, {"V_max", &p.V_max, true}},
               source);
  if (!prop["K_Q"]) {
    if (!prop["K_V"]) fail(source, "propulsion.K_Q", "missing required field (or give K_V in RPM/V)");
    if (!(p.K_V > 0)) fail(source, "propulsion.K_V", "value " + num(p.K_V) + " must be > 0 RPM/V");
    p.K_Q = 60.0 / (2.0 * 3.14159265358979323846 * p.K_V);
  }
  if (const YAML::Node s = doc["servos"]) {
    read_section(s, "servos",
                 {{"tau", &ac.servo_tau, false}, {"max_delta_a", &ac.max_delta_a, false},
                  {"max_delta_e", &ac.max_delta_e, false}, {"max_delta_r", &ac.max_delta_r, false}},
                 source);
  }
  ac.gear.points = default_gear_points(ac.b);
  if (const YAML::Node g = doc["gear"]) {
    auto& gr = ac.gear;
    read_section(g, "gear",
                 {{"static_deflection", &gr.static_deflection, false},
                  {"damping_ratio", &gr.damping_ratio, false}, {"mu_roll", &gr.mu_roll, false},
                  {"mu_lateral", &gr.mu_lateral, false}, {"v_slip", &gr.v_slip, false},
                  {"nose_steering", &gr.nose_steering, false}},
                 source, {"points"});
    if (const YAML::Node pts = g["points"]) {
      if (!pts.IsSequence() || pts.size() == 0) fail(source, "gear.points", "expected a list of [x, y, z]");
      gr.points.clear();
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const std::string f = "gear.points[" + std::to_string(i) + "]";
        if (!pts[i].IsSequence() || pts[i].size() != 3) fail(source, f, "expected [x, y, z] in m");
        gr.points.emplace_back(read_double(pts[i][0], source, f), read_double(pts[i][1], source, f),
                               read_double(pts[i][2], source, f));
      }
    }
  }
  return ac;
}

// ROSflight's names for the uavbook coefficients, and the ones its model declares but the
// uavbook model does not have (accepted only when zero).
Aircraft parse_rosflight(const YAML::Node& doc, const std::string& source) {
  Aircraft ac;
  ac.source = source;
  auto& a = ac.aero;
  auto& p = ac.prop;
  double epsilon = 0, refresh = 0, channel = 0, Jxy = 0, Jyz = 0;
  double max_a = ac.max_delta_a / kDeg, max_e = ac.max_delta_e / kDeg, max_r = ac.max_delta_r / kDeg;
  std::map<std::string, double*> known = {
      {"rho", &ac.rho}, {"mass", &ac.mass},
      {"wing_s", &ac.S}, {"wing_b", &ac.b}, {"wing_c", &ac.c}, {"wing_M", &ac.M},
      {"wing_epsilon", &epsilon}, {"wing_alpha0", &ac.alpha0},
      {"D_prop", &p.D_prop}, {"CT_0", &p.C_T_0}, {"CT_1", &p.C_T_1}, {"CT_2", &p.C_T_2},
      {"CQ_0", &p.C_Q_0}, {"CQ_1", &p.C_Q_1}, {"CQ_2", &p.C_Q_2}, {"KV", &p.K_V}, {"KQ", &p.K_Q},
      {"V_max", &p.V_max}, {"R_motor", &p.R_motor}, {"I_0", &p.i0},
      {"servo_tau", &ac.servo_tau}, {"servo_refresh_rate", &refresh},
      {"max_aileron_deflection_angle", &max_a}, {"max_elevator_deflection_angle", &max_e},
      {"max_rudder_deflection_angle", &max_r},
      {"aileron_channel", &channel}, {"elevator_channel", &channel},
      {"throttle_channel", &channel}, {"rudder_channel", &channel},
      {"C_L_O", &a.C_L_0}, {"C_L_alpha", &a.C_L_alpha}, {"C_L_q", &a.C_L_q},
      {"C_L_delta_e", &a.C_L_delta_e},
      {"C_D_O", &a.C_D_0}, {"C_D_alpha", &a.C_D_alpha}, {"C_D_p", &a.C_D_p}, {"C_D_q", &a.C_D_q},
      {"C_D_delta_e", &a.C_D_delta_e},
      {"C_ell_O", &a.C_ell_0}, {"C_ell_beta", &a.C_ell_beta}, {"C_ell_p", &a.C_ell_p},
      {"C_ell_r", &a.C_ell_r}, {"C_ell_delta_a", &a.C_ell_delta_a}, {"C_ell_delta_r", &a.C_ell_delta_r},
      {"C_m_O", &a.C_m_0}, {"C_m_alpha", &a.C_m_alpha}, {"C_m_q", &a.C_m_q},
      {"C_m_delta_e", &a.C_m_delta_e},
      {"C_n_O", &a.C_n_0}, {"C_n_beta", &a.C_n_beta}, {"C_n_p", &a.C_n_p}, {"C_n_r", &a.C_n_r},
      {"C_n_delta_a", &a.C_n_delta_a}, {"C_n_delta_r", &a.C_n_delta_r},
      {"C_Y_O", &a.C_Y_0}, {"C_Y_beta", &a.C_Y_beta}, {"C_Y_p", &a.C_Y_p}, {"C_Y_r", &a.C_Y_r},
      {"C_Y_delta_a", &a.C_Y_delta_a}, {"C_Y_delta_r", &a.C_Y_delta_r},
      {"Jxx", &ac.Jx}, {"Jyy", &ac.Jy}, {"Jzz", &ac.Jz}, {"Jxz", &ac.Jxz},
      {"Jxy", &Jxy}, {"Jyz", &Jyz}};
  static const std::set<std::string> kZeroOnly = {
      "C_L_beta", "C_L_p", "C_L_r", "C_L_delta_a", "C_L_delta_r", "C_D_beta", "C_D_r",
      "C_D_delta_a", "C_D_delta_r", "C_ell_alpha", "C_ell_q", "C_ell_delta_e", "C_m_beta",
      "C_m_p", "C_m_r", "C_m_delta_a", "C_m_delta_r", "C_n_alpha", "C_n_q", "C_n_delta_e",
      "C_Y_alpha", "C_Y_q", "C_Y_delta_e"};
  static const std::set<std::string> kNodes = {"/**", "/fixedwing_forces_and_moments",
                                               "fixedwing_forces_and_moments",
                                               "/standalone_dynamics", "standalone_dynamics"};
  std::set<std::string> seen;
  // Wildcard node first, so that node-specific values override it (ROS 2 semantics).
  std::vector<std::pair<std::string, YAML::Node>> nodes;
  for (const auto& kv : doc) {
    const std::string node = kv.first.as<std::string>();
    if (!kNodes.count(node)) fail(source, node, "unknown node (tern reads /**, /fixedwing_forces_and_moments, /standalone_dynamics)");
    if (node == "/**") nodes.insert(nodes.begin(), {node, kv.second});
    else nodes.emplace_back(node, kv.second);
  }
  for (const auto& [node, body] : nodes) {
    const YAML::Node params = body["ros__parameters"];
    if (!body.IsMap() || !params || !params.IsMap()) fail(source, node, "expected 'ros__parameters:' map");
    for (const auto& kv : params) {
      const std::string key = kv.first.as<std::string>();
      const std::string field = node + ".ros__parameters." + key;
      if (kZeroOnly.count(key)) {
        const double v = read_double(kv.second, source, field);
        if (v != 0.0) fail(source, field, "value " + num(v) + ": this coefficient is not part of the uavbook model tern implements (only 0 is accepted)");
        continue;
      }
      auto it = known.find(key);
      if (it == known.end()) fail(source, field, "unknown key");
      *it->second = read_double(kv.second, source, field);
      seen.insert(key);
    }
  }
  static const char* kRequired[] = {
      "rho", "mass", "wing_s", "wing_b", "wing_c", "wing_M", "wing_alpha0", "D_prop", "CT_0",
      "CT_1", "CT_2", "CQ_0", "CQ_1", "CQ_2", "V_max", "R_motor", "I_0", "C_L_O", "C_L_alpha",
      "C_L_q", "C_L_delta_e", "C_D_p", "C_D_q", "C_D_delta_e", "C_ell_O", "C_ell_beta", "C_ell_p",
      "C_ell_r", "C_ell_delta_a", "C_ell_delta_r", "C_m_O", "C_m_alpha", "C_m_q", "C_m_delta_e",
      "C_n_O", "C_n_beta", "C_n_p", "C_n_r", "C_n_delta_a", "C_n_delta_r", "C_Y_O", "C_Y_beta",
      "C_Y_p", "C_Y_r", "C_Y_delta_a", "C_Y_delta_r", "Jxx", "Jyy", "Jzz", "Jxz"};
  for (const char* k : kRequired) {
    if (!seen.count(k)) fail(source, k, "missing required field");
  }
  if (!seen.count("KQ")) {
    if (!seen.count("KV")) fail(source, "KQ", "missing required field (or give KV in RPM/V)");
    if (!(p.K_V > 0)) fail(source, "KV", "value " + num(p.K_V) + " must be > 0 RPM/V");
    p.K_Q = 60.0 / (2.0 * 3.14159265358979323846 * p.K_V);
  }
  if (Jxy != 0.0) fail(source, "Jxy", "value " + num(Jxy) + ": the uavbook model needs a symmetric aircraft (Jxy = 0)");
  if (Jyz != 0.0) fail(source, "Jyz", "value " + num(Jyz) + ": the uavbook model needs a symmetric aircraft (Jyz = 0)");
  ac.stall_blend = false;  // ROSflight's simulator sets sigma(alpha) = 0
  ac.e = 0.9;  // ROSflight's drag polar uses a fixed Oswald factor of 0.9 (wing_epsilon is unused)
  ac.max_delta_a = max_a * kDeg;
  ac.max_delta_e = max_e * kDeg;
  ac.max_delta_r = max_r * kDeg;
  ac.gear.points = default_gear_points(ac.b);
  const auto slash = source.find_last_of('/');
  ac.name = source.substr(slash == std::string::npos ? 0 : slash + 1);
  return ac;
}

}  // namespace

std::vector<ContactPoint> default_gear_points(double b) {
  return {ContactPoint(0.15 * b, 0.0, 0.06 * b), ContactPoint(-0.03 * b, 0.1 * b, 0.06 * b),
          ContactPoint(-0.03 * b, -0.1 * b, 0.06 * b)};
}

void validate(const Aircraft& ac) {
  const std::string& src = ac.source;
  auto positive = [&](double v, const char* field, const char* unit) {
    if (!std::isfinite(v) || !(v > 0)) fail(src, field, "value " + num(v) + " must be > 0 " + unit);
  };
  auto nonneg = [&](double v, const char* field, const char* unit) {
    if (!std::isfinite(v) || v < 0) fail(src, field, "value " + num(v) + " must be >= 0 " + unit);
  };
  positive(ac.mass, "mass", "kg");
  positive(ac.Jx, "inertia.Jx", "kg m^2");
  positive(ac.Jy, "inertia.Jy", "kg m^2");
  positive(ac.Jz, "inertia.Jz", "kg m^2");
  if (!std::isfinite(ac.Jxz) || ac.Jx * ac.Jz - ac.Jxz * ac.Jxz <= 0)
    fail(src, "inertia.Jxz", "value " + num(ac.Jxz) + " makes Jx Jz - Jxz^2 <= 0 (not an inertia)");
  positive(ac.rho, "environment.rho", "kg/m^3");
  positive(ac.S, "wing.S", "m^2");
  positive(ac.b, "wing.b", "m");
  positive(ac.c, "wing.c", "m");
  positive(ac.e, "wing.e", "");
  positive(ac.M, "wing.M", "");
  positive(ac.alpha0, "wing.alpha0", "rad");
  positive(ac.prop.D_prop, "propulsion.D_prop", "m");
  positive(ac.prop.K_Q, "propulsion.K_Q", "N m/A");
  positive(ac.prop.R_motor, "propulsion.R_motor", "ohm");
  nonneg(ac.prop.i0, "propulsion.i0", "A");
  positive(ac.prop.V_max, "propulsion.V_max", "V");
  if (!(ac.prop.C_Q_0 > 0)) fail(src, "propulsion.C_Q_0", "value " + num(ac.prop.C_Q_0) + " must be > 0 (static torque)");
  nonneg(ac.servo_tau, "servos.tau", "s");
  positive(ac.max_delta_a, "servos.max_delta_a", "rad");
  positive(ac.max_delta_e, "servos.max_delta_e", "rad");
  positive(ac.max_delta_r, "servos.max_delta_r", "rad");
  if (ac.gear.points.empty()) fail(src, "gear.points", "at least one contact point is needed");
  positive(ac.gear.static_deflection, "gear.static_deflection", "m");
  positive(ac.gear.damping_ratio, "gear.damping_ratio", "");
  nonneg(ac.gear.mu_roll, "gear.mu_roll", "");
  nonneg(ac.gear.mu_lateral, "gear.mu_lateral", "");
  positive(ac.gear.v_slip, "gear.v_slip", "m/s");
  nonneg(ac.gear.nose_steering, "gear.nose_steering", "rad/rad");
}

Aircraft parse_aircraft(const YAML::Node& doc, const std::string& source) {
  if (!doc || !doc.IsMap()) fail(source, "(document)", "expected a YAML map");
  bool ros = false;
  for (const auto& kv : doc) {
    const YAML::Node v = kv.second;
    if (v.IsMap() && v["ros__parameters"]) ros = true;
  }
  Aircraft ac = ros ? parse_rosflight(doc, source) : parse_tern(doc, source);
  validate(ac);
  return ac;
}

Aircraft load_aircraft(const std::string& path) {
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw std::runtime_error(path + ": cannot open aircraft file");
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": malformed YAML at line " + std::to_string(e.mark.line + 1) +
                             ": " + e.msg);
  }
  return parse_aircraft(doc, path);
}

}  // namespace tern::sim
