// emulator/world.cpp: see world.hpp.
#include "world.hpp"

#include "tern_sim_aero/wind.hpp"
#include "util.hpp"

namespace tern::fcu::emulator {

void place_aircraft(sim::Simulator& sim, const tern::Aircraft& ac, const Options& o) {
  const auto w = numbers(o.wind, 3, "--wind");
  sim.set_turbulence(sim::dryden_preset(o.turbulence));
  sim.set_steady_wind(Eigen::Vector3d(w[0], w[1], w[2]));
  if (o.init_mode == "ground")
    sim.set_state(sim::rest_state(ac, 0, 0, o.init_heading));
  else if (o.init_mode == "air")
    sim.set_state(sim::make_state({0, 0, -o.init_altitude}, {o.init_airspeed, 0, 0}, 0, 0, o.init_heading));
  else
    throw std::runtime_error("--init-mode: '" + o.init_mode + "' is not ground or air");
}

std::array<double, 3> servo_throw(const tern::Aircraft& ac, const std::string& max_deflection) {
  if (max_deflection.empty()) return {ac.max_delta_a, ac.max_delta_e, ac.max_delta_r};
  const auto m = numbers(max_deflection, 3, "--max-deflection");
  return {m[0], m[1], m[2]};
}

std::optional<std::pair<std::int64_t, std::int64_t>> time_window(const std::string& text, const std::string& option) {
  if (text.empty()) return std::nullopt;
  const auto s = numbers(text, 2, option);
  return std::make_pair(ns(s[0]), ns(s[1]));
}

}  // namespace tern::fcu::emulator
