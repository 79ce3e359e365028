// core/apps/sysid/logged_state.hpp: the uavbook model's state, inputs and wind at one sample of a
// flight series (flight_data.hpp), as validate and its one-step residuals start from them.
//   state  x = [p_n p_e p_d  u v w  e0..e3  p q r] (tern/aero/model.hpp): the estimator's
//          position NED and ground velocity in body FRD, its Euler angles (3-2-1) made into the
//          quaternion by make_state, and the body rates (gyro less the estimated bias)
//   inputs the commands in force (through the servo lag): delta_e delta_a delta_r (rad), delta_t
//   wind   the estimator's wind, NED, as the model's steady wind (no gust)
#pragma once

#include <cstddef>

#include "sysid/flight_data.hpp"
#include "tern/aero/model.hpp"

namespace tern::core::sysid {

inline sim::StateVector logged_state(const FlightSeries& s, std::size_t k) {
  return sim::make_state({s.p_n[k], s.p_e[k], s.p_d[k]}, {s.u[k], s.v[k], s.w[k]}, s.phi[k], s.theta[k], s.psi[k],
                         {s.p[k], s.q[k], s.r[k]});
}

inline sim::Deltas logged_deltas(const FlightSeries& s, std::size_t k) {
  sim::Deltas d;
  d.delta_e = s.delta_e[k], d.delta_a = s.delta_a[k], d.delta_r = s.delta_r[k], d.delta_t = s.delta_t[k];
  return d;
}

inline sim::Wind logged_wind(const FlightSeries& s, std::size_t k) {
  sim::Wind w;
  w.steady_ned = {s.w_n[k], s.w_e[k], s.w_d[k]};
  return w;
}

}  // namespace tern::core::sysid
