// Estimator: its configuration, events, sensor checks and time-outs, attitude helpers and its output (see estimator.hpp;
// the sensors: estimator_imu, _air, _gnss, _yaw; initialisation: estimator_init).
#include "tern/estimator_ekf/estimator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "tern/math.hpp"

namespace tern::ekf {

const char* sensor_name(Sensor s) {
  switch (s) {
    case Sensor::imu: return "imu";
    case Sensor::gnss: return "gnss";
    case Sensor::baro: return "baro";
    case Sensor::diff_pressure: return "diff_pressure";
    case Sensor::mag: return "mag";
  }
  return "?";
}

std::string describe(const Event& e) {
  char buf[200];
  const char* s = sensor_name(e.sensor);
  switch (e.kind) {
    case EventKind::origin_set:
      std::snprintf(buf, sizeof buf,
                    "origin set from the first fix passing every GNSS start-up check (%.1f s after the first fix); provisional "
                    "until they have held (on the ground the estimate is invalid till then)",
                    e.value);
      break;
    case EventKind::origin_dropped:
      std::snprintf(buf, sizeof buf,
                    "gnss: a start-up check failed before they had held: origin, estimate and barometer calibration dropped");
      break;
    case EventKind::gnss_epoch_ignored:
      std::snprintf(buf, sizeof buf,
                    "gnss: time_of_validity %.3f s before the fix's stamp, not a receiver's latency (another clock?): the stamps "
                    "less gnss_delay taken for every such fix",
                    e.value);
      break;
    case EventKind::gnss_checks_passed:
      std::snprintf(buf, sizeof buf, "gnss: start-up checks passed, %.1f s after the first fix", e.value);
      break;
    case EventKind::gnss_checks_failing: {
      const std::string names = gnss_check_names(static_cast<std::uint32_t>(e.value));
      std::snprintf(buf, sizeof buf, "gnss: waiting for the receiver to settle: %s",
                    names.empty() ? "every check passing, held" : names.c_str());
      break;
    }
    case EventKind::initialized:
      std::snprintf(buf, sizeof buf, "initialised (%s)",
                    e.value > 0.5 ? "yaw from magnetometer" : "no magnetometer: yaw from GNSS course or 0");
      break;
    case EventKind::baro_calibrated: std::snprintf(buf, sizeof buf, "barometer calibrated: altitude offset %.2f m", e.value); break;
    case EventKind::sensor_timeout: std::snprintf(buf, sizeof buf, "%s: time-out, no valid message for %.3f s", s, e.value); break;
    case EventKind::sensor_recovered: std::snprintf(buf, sizeof buf, "%s: valid messages again after %.3f s", s, e.value); break;
    case EventKind::gnss_reset:
      std::snprintf(buf, sizeof buf, "gnss: position rejected for too long, reset to GNSS (innovation %.1f m)", e.value);
      break;
    case EventKind::gsf_yaw_reset:
      std::snprintf(buf, sizeof buf,
                    "gnss: yaw disagreed with the yaw GSF's (IMU and GNSS velocity) in flight, reset to it (innovation %.1f deg); "
                    "magnetometer tested, not fused, until its heading agrees",
                    e.value);
      break;
    case EventKind::gnss_velocity_reset:
      std::snprintf(buf, sizeof buf, "gnss: velocity rejected in flight, velocity and position reset to GNSS (innovation %.1f m/s)",
                    e.value);
      break;
    case EventKind::imu_gap: std::snprintf(buf, sizeof buf, "imu: gap of %.3f s between samples (propagation clamped)", e.value); break;
    case EventKind::filter_reset:
      std::snprintf(buf, sizeof buf, "filter diverged (non-finite state or covariance): re-initialising");
      break;
    case EventKind::mag_reset:
      std::snprintf(buf, sizeof buf, "mag: heading rejected for too long, yaw reset to the magnetometer (innovation %.1f deg)", e.value);
      break;
    case EventKind::gnss_yaw_reset:
    case EventKind::launch_yaw_alignment:
      std::snprintf(buf, sizeof buf, "gnss: %s (%s %.1f deg); magnetometer tested, not fused, until its heading agrees",
                    e.kind == EventKind::gnss_yaw_reset ? "velocity rejected in flight, yaw reset to the GNSS course"
                                                        : "yaw aligned in flight to the GNSS course after the launch",
                    e.kind == EventKind::gnss_yaw_reset ? "innovation" : "turned", e.value);
      break;
    case EventKind::mag_resumed:
      std::snprintf(buf, sizeof buf, "mag: heading consistent with the yaw again, fusion resumed (%.1f s after the yaw reset)", e.value);
      break;
    case EventKind::inflated:
      std::snprintf(buf, sizeof buf, "%s: rejected repeatedly, variance of the states it measures inflated x%.1f", s, e.value);
      break;
    case EventKind::imu_lost:
      std::snprintf(buf, sizeof buf, "imu: silent for %.3f s, attitude lost: re-initialising in flight", e.value);
      break;
    case EventKind::too_old:
      std::snprintf(buf, sizeof buf, "%s: sample valid %.3f s ago, older than the state history: dropped", s, e.value);
      break;
    case EventKind::first_invalid:
      std::snprintf(buf, sizeof buf,
                    "%s: invalid sample rejected (NaN/Inf, out of range or stamp going back); further ones are only counted", s);
      break;
  }
  return buf;
}

Estimator::Estimator(const EstimatorConfig& config) {
  events_.reserve(32);
  set_config(config);
}

void Estimator::set_config(const EstimatorConfig& config) {
  cfg_ = config;
  apply_models_config();
}

namespace {
/// G with mu = G b_a: the board's tilt (roll, pitch) that a level calibration put into the
/// accelerometer offset, b_a = [mu]x (0, 0, -g) (EstimatorConfig::accel_level_calibrated).
Mat3 level_tilt_from_offset(double g) {
  Mat3 G = Mat3::Zero();
  G(0, 1) = 1.0 / g;
  G(1, 0) = -1.0 / g;
  return G;
}
}  // namespace

void Estimator::apply_models_config() {
  process_ = cfg_.process;
  gnss_checks_.set_config(cfg_.gnss_checks);
  filter_.set_covariance_period(cfg_.covariance_period);
  R_bi_ = rotation_from_euler(cfg_.imu_mount.x(), cfg_.imu_mount.y(), cfg_.imu_mount.z());
  gnss_pos_.antenna = cfg_.gnss_antenna;
  gnss_vel_.antenna = cfg_.gnss_antenna;
  gnss_pos_.sigma_h = cfg_.gnss_pos_sigma_h;
  gnss_pos_.sigma_v = cfg_.gnss_pos_sigma_v;
  gnss_pos_.gate = cfg_.gnss_pos_gate;
  gnss_vel_.sigma_h = gnss_vel_sigma_h_ = cfg_.gnss_vel_sigma_h;
  gnss_vel_.sigma_v = gnss_vel_sigma_v_ = cfg_.gnss_vel_sigma_v;
  gnss_vel_.gate = cfg_.gnss_vel_gate;
  gnss_vel_ne_.gate = cfg_.gnss_vel_gate * kChi2_999[2] / kChi2_999[3];  // the same confidence with 2 dof
  tern::MagneticField fixed;
  fixed.declination = cfg_.mag_declination;
  fixed.inclination = cfg_.mag_inclination;
  fixed.intensity = cfg_.mag_field_strength;
  fixed.model = "configured";
  set_earth_field(fixed);
  mag_.sigma = cfg_.mag_sigma;
  mag_.gate = cfg_.mag_gate;
  mag_heading_.sigma = cfg_.mag_sigma;
  mag_heading_.gate = cfg_.mag_heading_gate;
  baro_.sigma = cfg_.baro_sigma / (cfg_.rho * cfg_.gravity);
  baro_.rho_g = cfg_.rho * cfg_.gravity;
  baro_.cross_flow_sigma = cfg_.baro_cross_flow_sigma;
  baro_.gravity = cfg_.gravity;
  baro_.gate = cfg_.baro_gate;
  pitot_.rho = cfg_.rho;
  pitot_.sigma = cfg_.diff_pressure_sigma;
  pitot_.gust_sigma = cfg_.airspeed_gust_sigma;
  pitot_.gate = cfg_.diff_pressure_gate;
  pitot_.min_airspeed = cfg_.min_airspeed;
  sideslip_.sigma = cfg_.sideslip_sigma;
  sideslip_.gate = cfg_.sideslip_gate;
  sideslip_.min_airspeed = cfg_.min_airspeed;
  const double k_aero = cfg_.rho * cfg_.wing_S / (2.0 * cfg_.mass);  // rho S / (2 m), 1/m: force per q_bar C, over the mass
  side_force_.k = cfg_.side_force_active() ? k_aero : 0.0;
  side_force_.C_Y_0 = cfg_.C_Y_0;
  side_force_.C_Y_beta = cfg_.C_Y_beta;
  side_force_.C_Y_delta_a = cfg_.C_Y_delta_a;
  side_force_.C_Y_delta_r = cfg_.C_Y_delta_r;
  side_force_.sigma = cfg_.side_force_sigma;
  side_force_.gust_sigma = cfg_.airspeed_gust_sigma;
  side_force_.gate = cfg_.side_force_gate;
  side_force_.min_airspeed = cfg_.min_airspeed;
  normal_force_.k = cfg_.normal_force_active() ? k_aero : 0.0;
  normal_force_.C_L_0 = cfg_.C_L_0;
  normal_force_.C_L_alpha = cfg_.C_L_alpha;
  normal_force_.C_L_q = cfg_.C_L_q;
  normal_force_.C_L_delta_e = cfg_.C_L_delta_e;
  normal_force_.chord = cfg_.wing_c;
  normal_force_.sigma = cfg_.normal_force_sigma;
  normal_force_.min_airspeed = cfg_.min_airspeed;
  normal_force_.level_G = cfg_.accel_level_calibrated ? level_tilt_from_offset(cfg_.gravity) : Mat3::Zero();
}

void Estimator::set_earth_field(const tern::MagneticField& f) {
  field_ = f;
  mag_.declination = mag_heading_.declination = f.declination;
  mag_.inclination = mag_heading_.inclination = f.inclination;
  mag_.field_strength = mag_heading_.field_strength = f.intensity;
}

void Estimator::reset() {
  Estimator fresh(cfg_);
  fresh.expect_mag_ = expect_mag_;
  fresh.expected_ = expected_;
  *this = std::move(fresh);
}

void Estimator::push(Nanos stamp, EventKind kind, Sensor s, double value) { events_.push_back(Event{stamp, kind, s, value}); }

std::vector<Event> Estimator::take_events() {
  std::vector<Event> out;
  out.swap(events_);
  events_.reserve(32);
  return out;
}

bool Estimator::accept(Sensor s, Nanos stamp, bool ok) {
  SensorCounters& c = counters_[static_cast<int>(s)];
  ++c.received;
  if (!ok || (c.last_stamp >= 0 && stamp < c.last_stamp)) {
    if (c.invalid++ == 0) push(stamp, EventKind::first_invalid, s);
    return false;
  }
  if (c.timed_out) {
    c.timed_out = false;
    push(stamp, EventKind::sensor_recovered, s, to_seconds(stamp - (c.last_stamp >= 0 ? c.last_stamp : first_check_)));
  }
  c.last_stamp = stamp;
  return true;
}

void Estimator::check_timeouts(Nanos now) {
  if (first_check_ < 0) first_check_ = now;
  for (int i = 0; i < kSensorCount; ++i) {
    SensorCounters& c = counters_[i];
    const Nanos since = c.last_stamp >= 0 ? c.last_stamp : expected_[i] ? first_check_ : -1;
    if (since < 0 || c.timed_out) continue;
    const double silent = to_seconds(now - since);
    if (silent > cfg_.timeout[i]) {
      c.timed_out = true;
      ++c.timeouts;
      push(now, EventKind::sensor_timeout, static_cast<Sensor>(i), silent);
    }
  }
}

Eigen::Quaterniond Estimator::attitude_from_accel(const Vec3& f, double psi) {
  // At rest f = -R^T g e3 = g (sin theta, -sin phi cos theta, -cos phi cos theta).
  const double phi = std::atan2(-f.y(), -f.z());
  const double theta = std::atan2(f.x(), std::hypot(f.y(), f.z()));
  return quaternion_from_euler(phi, theta, psi);
}

Eigen::Quaterniond Estimator::attitude_triad(const Vec3& f_body, const Vec3& f_ned, const Vec3& m_body, const Vec3& m_ned) {
  const Vec3 c_b = f_body.cross(m_body), c_n = f_ned.cross(m_ned);
  if (f_body.norm() < 1e-9 || f_ned.norm() < 1e-9 || c_b.norm() < 1e-9 * f_body.norm() * m_body.norm() ||
      c_n.norm() < 1e-9 * f_ned.norm() * m_ned.norm()) {
    throw std::invalid_argument("attitude_triad: a zero vector or parallel vector pairs");
  }
  Mat3 B, N;  // orthonormal triads in body and NED
  B.col(0) = f_body.normalized();
  B.col(1) = c_b.normalized();
  B.col(2) = B.col(0).cross(B.col(1));
  N.col(0) = f_ned.normalized();
  N.col(1) = c_n.normalized();
  N.col(2) = N.col(0).cross(N.col(1));
  return Eigen::Quaterniond(Mat3(N * B.transpose())).normalized();  // R B = N
}

Eigen::Quaterniond Estimator::attitude_from_accel_mag(const Vec3& f, const Vec3& m, double declination) {
  const double phi = std::atan2(-f.y(), -f.z());
  const double theta = std::atan2(f.x(), std::hypot(f.y(), f.z()));
  // Field in the level (yaw-only) frame: m_l = R_y(theta) R_x(phi) m_b = Rz(psi)^T m_n, whose
  // horizontal part points at (declination - psi).
  const Vec3 m_l = rotation_from_euler(phi, theta, 0.0) * m;
  const double psi = wrap_pi(declination - std::atan2(m_l.y(), m_l.x()));
  return quaternion_from_euler(phi, theta, psi);
}

Vec3 Estimator::ned_from_geodetic(double lat, double lon, double alt) const { return origin_->to_ned(lat, lon, alt); }

msg::State Estimator::state() const {
  msg::State s;
  fill_state(s);
  return s;
}

Eigen::Quaterniond Estimator::body_attitude() const {
  const NominalState& x = filter_.x();
  if (!cfg_.accel_level_calibrated) return x.q;
  LevelTilt& t = level_tilt_;
  if (!(x.b_a == t.b_a) || cfg_.gravity != t.gravity) t = {x.b_a, cfg_.gravity, quat_exp(-level_tilt_from_offset(cfg_.gravity) * x.b_a)};
  return (x.q * t.exp_minus_mu).normalized();
}

Vec3 Estimator::body_attitude_variance() const {
  const Cov& P = filter_.P();
  const Vec3 mount2 = cfg_.imu_mount_sigma.cwiseProduct(cfg_.imu_mount_sigma);
  if (!cfg_.accel_level_calibrated) return P.block<3, 3>(idx::th, idx::th).diagonal() + mount2;
  // dtheta_body = dtheta - G db_a (mu is a few tenths of a degree: its rotation of dtheta is
  // second order); roll and pitch as level as the calibration's floor, yaw as the mount.
  const Mat3 G = level_tilt_from_offset(cfg_.gravity);
  const Mat3 Ptb = P.block<3, 3>(idx::th, idx::ba) * G.transpose();
  const Mat3 Pb = P.block<3, 3>(idx::th, idx::th) - Ptb - Ptb.transpose() + G * P.block<3, 3>(idx::ba, idx::ba) * G.transpose();
  const double l2 = cfg_.level_sigma * cfg_.level_sigma;
  return Pb.diagonal() + Vec3(l2, l2, mount2.z());
}

void Estimator::fill_state(msg::State& s) const {
  const NominalState& x = filter_.x();
  s.stamp = std::max<Nanos>(imu_stamp_, 0);
  s.origin_lat = origin_lat_;
  s.origin_lon = origin_lon_;
  s.origin_alt = origin_alt_;
  s.origin_valid = origin_valid();
  s.status = status(&s.degraded_sensors);
  s.valid = s.status != msg::StateStatus::invalid;
  s.p_n = x.p.x() + output_offset_.x();
  s.p_e = x.p.y() + output_offset_.y();
  s.p_d = x.p.z() + output_offset_.z();
  s.v_n = x.v.x();
  s.v_e = x.v.y();
  s.v_d = x.v.z();
  const Eigen::Quaterniond q = body_attitude();
  const Vec3 vb = q.conjugate() * x.v;
  s.u = vb.x();
  s.v = vb.y();
  s.w = vb.z();
  const Vec3 e = euler_from_quaternion(q);
  s.phi = e.x();
  s.theta = e.y();
  s.psi = e.z();
  s.quat = q;
  s.p = rate_.x();
  s.q = rate_.y();
  s.r = rate_.z();
  const Vec3 vr = q.conjugate() * (x.v - x.wind_ned());
  s.Va = vr.norm();
  s.alpha = std::atan2(vr.z(), vr.x());
  s.beta = s.Va > 1e-3 ? std::asin(std::clamp(vr.y() / s.Va, -1.0, 1.0)) : 0.0;
  s.Vg = x.v.norm();
  s.chi = wrap_pi(std::atan2(x.v.y(), x.v.x()));
  s.gamma = s.Vg > 1e-3 ? std::asin(std::clamp(-x.v.z() / s.Vg, -1.0, 1.0)) : 0.0;
  s.w_n = x.wind.x();
  s.w_e = x.wind.y();
  s.w_d = x.wind_d;
  s.b_x = x.b_g.x();
  s.b_y = x.b_g.y();
  s.b_z = x.b_g.z();
  const Cov& P = filter_.P();
  static_assert(static_cast<int>(std::tuple_size_v<decltype(s.P_diag)>) == idx::sg);  // the navigation states
  for (std::size_t i = 0; i < s.P_diag.size(); ++i) s.P_diag[i] = P(static_cast<int>(i), static_cast<int>(i));
  const Vec3 att = body_attitude_variance();
  for (int i = 0; i < 3; ++i) s.P_diag[static_cast<std::size_t>(idx::th + i)] = att[i];
  // The barometer measures the height above its calibration datum, known to decimetres; the
  // altitude in the frame is as uncertain as that datum (the origin, a GNSS fix, off by metres).
  // Without it the published altitude claimed the baro's accuracy: position NEES 9-11 per
  // dimension on the worst seeds of bench_estimation (realistic profile).
  if (baro_calibrated_) s.P_diag[static_cast<std::size_t>(idx::p + 2)] += baro_datum_var_;
}

}  // namespace tern::ekf
