// tern-aero: the simulator's aircraft model on the command line (`tern aero ...` runs it).
//
//   tern-aero eval --aircraft FILE --state JSON --delta JSON [--wind JSON]
//       Air data, propeller, body forces and moments, and the 13-state derivative at one state.
//       state: {"p_n","p_e","p_d","u","v","w", "phi","theta","psi" | "e0","e1","e2","e3", "p","q","r"}
//       delta: {"delta_e","delta_a","delta_r","delta_t"}; wind: {"w_n","w_e","w_d","u_g","v_g","w_g"}
//       (steady NED and gust body parts). Missing keys are 0; unknown keys are errors.
//   tern-aero trim --aircraft FILE --Va V [--gamma G] [--radius R] [--altitude H]
//       Trim state and inputs (Beard & McLain, ch. 5); R in m (> 0 right turn; omit: straight).
// Output: JSON on stdout. Errors: one line on stderr, exit status 1.
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "tern_sim_aero/aircraft.hpp"
#include "tern_sim_aero/model.hpp"
#include "tern_sim_aero/trim.hpp"

using json = nlohmann::ordered_json;
namespace sim = tern::sim;

namespace {

// Parses a JSON object of numbers with the allowed keys; "what" names it in errors.
std::map<std::string, double> parse_object(const std::string& text, const std::string& what,
                                           const std::set<std::string>& allowed) {
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
  const sim::Aircraft ac = sim::load_aircraft(file);
  const auto st = parse_object(state_s, "state",
                               {"p_n", "p_e", "p_d", "u", "v", "w", "phi", "theta", "psi", "e0", "e1", "e2",
                                "e3", "p", "q", "r"});
  const bool euler = st.count("phi") || st.count("theta") || st.count("psi");
  const bool quat = st.count("e0") || st.count("e1") || st.count("e2") || st.count("e3");
  if (euler && quat) throw std::runtime_error("--state: give either phi/theta/psi or e0..e3, not both");
  sim::StateVector x = sim::make_state({get(st, "p_n"), get(st, "p_e"), get(st, "p_d")},
                                       {get(st, "u"), get(st, "v"), get(st, "w")}, get(st, "phi"),
                                       get(st, "theta"), get(st, "psi"), {get(st, "p"), get(st, "q"), get(st, "r")});
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
                                 "e1_dot", "e2_dot", "e3_dot", "p_dot", "q_dot", "r_dot"};
  for (int i = 0; i < 13; ++i) dj[kDot[i]] = dx[i];
  out["derivative"] = dj;
  std::cout << out.dump(2) << "\n";
  return 0;
}

int trim(const std::string& file, double Va, double gamma, double R, double altitude) {
  const sim::Aircraft ac = sim::load_aircraft(file);
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
  if (std::isinf(R)) out["R"] = nullptr;
  else out["R"] = R;
  out["alpha"] = t.alpha;
  out["beta"] = t.beta;
  out["phi"] = t.phi;
  out["theta"] = t.theta;
  out["delta"] = json{{"delta_e", t.delta.delta_e}, {"delta_a", t.delta.delta_a},
                      {"delta_r", t.delta.delta_r}, {"delta_t", t.delta.delta_t}};
  out["state"] = state_json(t.x);
  out["residual"] = t.residual;
  out["iterations"] = t.iterations;
  std::cout << out.dump(2) << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tern aero: the sim_aero aircraft model (Beard & McLain) on the command line"};
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

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (ev->parsed()) return eval(file, state_s, delta_s, wind_s);
    return trim(file, Va, gamma, R, altitude);
  } catch (const std::exception& e) {
    std::cerr << "tern aero: " << e.what() << "\n";
    return 1;
  }
}
