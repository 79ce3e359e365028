// The simulated aircraft (see simulator.hpp).
#include "tern_sim_aero/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tern::sim {

std::string first_non_finite(const StateVector& x) {
  static const char* kNames[13] = {"p_n", "p_e", "p_d", "u", "v", "w", "e0", "e1", "e2", "e3", "p", "q", "r"};
  for (int i = 0; i < 13; ++i) {
    if (!std::isfinite(x[i])) return kNames[i];
  }
  return {};
}

namespace {
// One servo over dt: no motion while the command error is inside the deadband; otherwise the
// fraction k of the error (first-order lag), at most rate_limit * dt.
double servo_step(double pos, double cmd, double k, double dt, const ActuatorParams& a) {
  const double err = cmd - pos;
  if (std::fabs(err) <= 0.5 * a.servo_deadband) return pos;
  double move = k * err;
  if (a.servo_rate_limit > 0) move = std::clamp(move, -a.servo_rate_limit * dt, a.servo_rate_limit * dt);
  return pos + move;
}
}  // namespace

ActuatorParams actuator_profile(std::string_view name) {
  if (name == "rosflight" || name == "ideal") return {};
  if (name == "realistic") {
    ActuatorParams a;
    a.servo_rate_limit = (60.0 * 3.14159265358979323846 / 180.0) / 0.10;  // 0.10 s / 60 deg
    a.servo_deadband = 0.003;                                             // 2 us of a +-500 us pulse over +-0.7 rad
    a.motor_tau = 0.1;
    return a;
  }
  throw std::invalid_argument("unknown sensor profile '" + std::string(name) + "' (valid: rosflight, realistic, ideal)");
}

Simulator::Simulator(Aircraft ac, std::uint64_t seed) : ac_(std::move(ac)), seed_(seed), rng_(seed) {
  // Level at rest height: cheap; rest_state() gives the settled attitude when it matters.
  x_ = make_state(Eigen::Vector3d(0, 0, -rest_height(ac_)), Eigen::Vector3d::Zero(), 0, 0, 0);
}

void Simulator::set_state(const StateVector& x, const Deltas& surfaces) {
  const std::string bad = first_non_finite(x);
  if (!bad.empty()) throw std::runtime_error("initial state: " + bad + " is not finite");
  if (x.segment<4>(E0).norm() < 1e-9) throw std::runtime_error("initial state: quaternion is zero");
  x_ = x;
  x_.segment<4>(E0).normalize();
  act_ = surfaces;
  act_.delta_a = std::clamp(act_.delta_a, -ac_.max_delta_a, ac_.max_delta_a);
  act_.delta_e = std::clamp(act_.delta_e, -ac_.max_delta_e, ac_.max_delta_e);
  act_.delta_r = std::clamp(act_.delta_r, -ac_.max_delta_r, ac_.max_delta_r);
  act_.delta_t = std::clamp(act_.delta_t, 0.0, 1.0);
  cmd_ = act_;
  t_ = 0;
  crashed_ = false;
  impact_ = Impact{};
}

void Simulator::set_command(const Deltas& c) {
  const char* bad = !std::isfinite(c.delta_a)   ? "delta_a"
                    : !std::isfinite(c.delta_e) ? "delta_e"
                    : !std::isfinite(c.delta_r) ? "delta_r"
                    : !std::isfinite(c.delta_t) ? "delta_t"
                                                : nullptr;
  if (bad != nullptr) throw std::runtime_error(std::string("actuators: ") + bad + " is not finite");
  cmd_.delta_a = std::clamp(c.delta_a, -ac_.max_delta_a, ac_.max_delta_a);
  cmd_.delta_e = std::clamp(c.delta_e, -ac_.max_delta_e, ac_.max_delta_e);
  cmd_.delta_r = std::clamp(c.delta_r, -ac_.max_delta_r, ac_.max_delta_r);
  cmd_.delta_t = std::clamp(c.delta_t, 0.0, 1.0);
}

Eigen::Vector3d Simulator::wind_ned() const { return wind_.steady_ned + attitude(x_) * wind_.gust_body; }

void Simulator::reset_wind() {
  rng_.seed(seed_);
  dryden_.reset();
  gusts_.reset();
  wind_ = Wind{};
}

ForcesMoments Simulator::evaluate() const { return forces_moments(ac_, x_, act_, wind_); }

void Simulator::step(double dt) {
  if (!(dt > 0)) return;
  t_ += dt;
  // Servos: deadband, first-order lag (exact for a command held over the step), rate limit.
  const double k = ac_.servo_tau > 0 ? 1.0 - std::exp(-dt / ac_.servo_tau) : 1.0;
  act_.delta_a = servo_step(act_.delta_a, cmd_.delta_a, k, dt, actuators_);
  act_.delta_e = servo_step(act_.delta_e, cmd_.delta_e, k, dt, actuators_);
  act_.delta_r = servo_step(act_.delta_r, cmd_.delta_r, k, dt, actuators_);
  const double km = actuators_.motor_tau > 0 ? 1.0 - std::exp(-dt / actuators_.motor_tau) : 1.0;
  act_.delta_t += km * (cmd_.delta_t - act_.delta_t);
  // Wind: turbulence driven at the current airspeed, gusts at the new time.
  const double Va = air_data(x_, wind_).Va;
  wind_.gust_body = dryden_.step(dt, Va, rng_);
  wind_.steady_ned = steady_ + gusts_.step(t_, rng_);
  if (crashed_) return;
  const StateVector xn = rk4_step(ac_, x_, act_, wind_, dt);
  const std::string bad = first_non_finite(xn);
  if (!bad.empty()) {
    throw std::runtime_error("simulation diverged at t = " + std::to_string(t_) + " s: state " + bad + " is not finite");
  }
  x_ = xn;
  if (x_[PD] > 0.0) {  // CG below the ground: a crash, not a flight
    crashed_ = true;
    impact_ = Impact{t_, x_, air_data(x_, wind_).Va};
    x_[PD] = 0.0;
    x_.segment<3>(U).setZero();
    x_.segment<3>(P).setZero();
  }
}

}  // namespace tern::sim
