// core/apps/sysid/validate_simulation.cpp: the uavbook model flown open loop over each window by
// the logged commands, from the logged state (validate.hpp: Simulation).
#include <algorithm>
#include <cmath>
#include <limits>

#include "sysid/logged_state.hpp"
#include "sysid/validate.hpp"

namespace tern::core::sysid {

namespace {

/// The scored channels of state x in the wind w, in kChannelSpecs' order.
std::array<double, kChannels> outputs(const sim::StateVector& x, const sim::Wind& w) {
  const sim::AirData air = sim::air_data(x, w);
  const Eigen::Vector3d euler = euler_from_quaternion(sim::attitude(x));
  return {x[sim::P], x[sim::Q], x[sim::R], air.Va, air.alpha, air.beta, euler.x(), euler.y()};
}

/// x advanced by dt (s) with the inputs d and wind w held, in RK4 steps of at most max_step.
sim::StateVector advance(const Aircraft& ac, sim::StateVector x, const sim::Deltas& d, const sim::Wind& w, double dt, double max_step) {
  const int steps = std::max(1, static_cast<int>(std::ceil(dt / max_step)));
  for (int i = 0; i < steps && sim::all_finite(x); ++i) x = sim::rk4_step(ac, x, d, w, dt / steps);
  return x;
}

/// One window: the prediction at each of its samples; true if the state stopped being finite.
bool simulate_window(const FlightSeries& s, const Aircraft& ac, const Window& win, const ValidateOptions& o, Prediction& out) {
  sim::StateVector x = logged_state(s, win.begin);
  const sim::Wind wind = logged_wind(s, win.begin);
  std::array<double, kChannels> y = outputs(x, wind);
  bool diverged = false;
  for (std::size_t k = win.begin; k < win.end; ++k) {
    if (k > win.begin && !diverged) {
      x = advance(ac, x, logged_deltas(s, k - 1), wind, s.t[k] - s.t[k - 1], o.max_step);
      diverged = !sim::all_finite(x);
      if (!diverged) y = outputs(x, wind);  // else the last finite prediction is held
    }
    for (std::size_t c = 0; c < kChannels; ++c) out.channel[c][k] = y[c];
  }
  return diverged;
}

}  // namespace

Prediction simulate_windows(const FlightSeries& s, const Aircraft& ac, const std::vector<Window>& windows, const ValidateOptions& o) {
  Prediction out;
  for (auto& c : out.channel) c.assign(s.size(), std::numeric_limits<double>::quiet_NaN());
  for (const Window& w : windows)
    if (simulate_window(s, ac, w, o, out)) ++out.diverged;
  return out;
}

}  // namespace tern::core::sysid
