// The simulated aircraft (see simulator.hpp).
#include "tern_sim_aero/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
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
  wheel_down_.assign(ac_.gear.points.size(), false);
  {
    const Eigen::Matrix3d Rot = attitude(x_).toRotationMatrix();
    for (std::size_t i = 0; i < ac_.gear.points.size(); ++i)
      wheel_down_[i] = (Eigen::Vector3d(x_[PN], x_[PE], x_[PD]) + Rot * ac_.gear.points[i]).z() > 0.0;
  }
}

void Simulator::set_command(const Deltas& c) {
  const char* bad = !std::isfinite(c.delta_a)   ? "delta_a"
                    : !std::isfinite(c.delta_e) ? "delta_e"
                    : !std::isfinite(c.delta_r) ? "delta_r"
                    : !std::isfinite(c.delta_t) ? "delta_t"
                    : !std::isfinite(c.brake)   ? "brake"
                                                : nullptr;
  if (bad != nullptr) throw std::runtime_error(std::string("actuators: ") + bad + " is not finite");
  cmd_.delta_a = std::clamp(c.delta_a, -ac_.max_delta_a, ac_.max_delta_a);
  cmd_.delta_e = std::clamp(c.delta_e, -ac_.max_delta_e, ac_.max_delta_e);
  cmd_.delta_r = std::clamp(c.delta_r, -ac_.max_delta_r, ac_.max_delta_r);
  cmd_.delta_t = std::clamp(c.delta_t, 0.0, 1.0);
  cmd_.brake = std::clamp(c.brake, 0.0, 1.0);
}

Eigen::Vector3d Simulator::wind_ned() const { return wind_.steady_ned + attitude(x_) * wind_.gust_body; }

void Simulator::reset_wind() {
  rng_.seed(seed_);
  dryden_.reset();
  gusts_.reset();
  wind_ = Wind{};
}

ForcesMoments Simulator::evaluate() const { return forces_moments(ac_, x_, act_, wind_); }

// A hard point below the ground, or a wheel touching down faster than the gear's max_sink_rate
// (its vertical speed when it first touches): fills what struck and how fast into m.
bool Simulator::ground_strike(Impact& m) {
  const Eigen::Matrix3d Rot = attitude(x_).toRotationMatrix();
  const Eigen::Vector3d p(x_[PN], x_[PE], x_[PD]), v(x_[U], x_[V], x_[W]), w(x_[P], x_[Q], x_[R]);
  auto speed_of = [&](const Eigen::Vector3d& r) { return Eigen::Vector3d(Rot * (v + w.cross(r))); };
  char buf[160];
  const auto& st = ac_.gear.structure;
  for (std::size_t i = 0; i < st.size(); ++i) {
    if ((p + Rot * st[i].second).z() <= 0.0) continue;
    const Eigen::Vector3d vi = speed_of(st[i].second);
    std::snprintf(buf, sizeof buf, "the %s struck the ground at %.1f m/s (sink %.1f m/s)", st[i].first.c_str(), vi.norm(), vi.z());
    m.what = buf;
    m.hard_point = static_cast<int>(i);
    m.point_speed = vi.norm();
    m.point_sink = vi.z();
    return true;
  }
  const auto& pts = ac_.gear.points;
  wheel_down_.resize(pts.size(), false);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const bool down = (p + Rot * pts[i]).z() > 0.0;
    const Eigen::Vector3d vi = speed_of(pts[i]);
    const bool first = down && !wheel_down_[i];
    wheel_down_[i] = down;
    if (first && vi.z() > ac_.gear.max_sink_rate) {
      std::snprintf(buf, sizeof buf, "hard touchdown: wheel %zu (%s) at %.1f m/s sink > the gear's %.1f m/s", i,
                    pts[i].x() > 0.0 ? "nose" : (pts[i].y() >= 0.0 ? "right main" : "left main"), vi.z(), ac_.gear.max_sink_rate);
      m.what = buf;
      m.wheel = static_cast<int>(i);
      m.point_speed = vi.norm();
      m.point_sink = vi.z();
      return true;
    }
  }
  return false;
}

double Simulator::Lag::operator()(double step, double time_constant) {
  if (step != dt || time_constant != tau) {
    dt = step;
    tau = time_constant;
    k = tau > 0 ? 1.0 - std::exp(-dt / tau) : 1.0;
  }
  return k;
}

void Simulator::step(double dt) {
  if (!(dt > 0)) return;
  t_ += dt;
  // Servos: deadband, first-order lag (exact for a command held over the step), rate limit.
  const double k = servo_lag_(dt, ac_.servo_tau);
  act_.delta_a = servo_step(act_.delta_a, cmd_.delta_a, k, dt, actuators_);
  act_.delta_e = servo_step(act_.delta_e, cmd_.delta_e, k, dt, actuators_);
  act_.delta_r = servo_step(act_.delta_r, cmd_.delta_r, k, dt, actuators_);
  const double km = motor_lag_(dt, actuators_.motor_tau);
  act_.delta_t += km * (cmd_.delta_t - act_.delta_t);
  act_.brake = cmd_.brake;
  // Wind: turbulence at the height of the CG, driven at the speed through the air mass without
  // the turbulence itself (the frozen field's speed; with the gust in it, a parked aircraft's
  // gust fed its own time scale and grew without bound); gusts at the new time.
  Wind mean = wind_;
  mean.gust_body.setZero();
  wind_.gust_body = dryden_.step(dt, airspeed(x_, mean), -x_[PD], steady_.head<2>().norm(), rng_);
  wind_.steady_ned = steady_ + gusts_.step(t_, rng_);
  if (crashed_) return;
  const StateVector xn = rk4_step(ac_, x_, act_, wind_, dt);
  const std::string bad = first_non_finite(xn);
  if (!bad.empty()) {
    throw std::runtime_error("simulation diverged at t = " + std::to_string(t_) + " s: state " + bad + " is not finite");
  }
  x_ = xn;
  Impact m;
  if (x_[PD] > 0.0) {
    const Eigen::Vector3d v_ned = attitude(x_) * Eigen::Vector3d(x_[U], x_[V], x_[W]);
    m.what = "the CG went below the ground";
    m.point_speed = v_ned.norm();
    m.point_sink = v_ned.z();
  }
  if (!m.what.empty() || ground_strike(m)) {  // a crash, not a flight
    crashed_ = true;
    m.t = t_;
    m.x = x_;
    m.Va = air_data(x_, wind_).Va;
    impact_ = std::move(m);
    x_[PD] = std::min(x_[PD], 0.0);
    x_.segment<3>(U).setZero();
    x_.segment<3>(P).setZero();
  }
}

}  // namespace tern::sim
