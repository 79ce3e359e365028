// Sensor models (see sensors.hpp).
#include "tern_sim_aero/sensors.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "tern/math.hpp"
#include "tern_sim_aero/earth_field.hpp"
#include "tern/atmosphere.hpp"

namespace tern::sim {

double standard_temperature(double h) { return 288.15 - 0.0065 * h; }

double standard_pressure(double h) { return tern::isa_pressure(h); }

// WGS-84 geodetic <-> ECEF <-> local NED (see WorldGeodesy in sensors.hpp).
namespace {
constexpr double kWgs84A = 6378137.0;                   // semi-major axis, m
constexpr double kWgs84F = 1.0 / 298.257223563;         // flattening
constexpr double kWgs84E2 = kWgs84F * (2.0 - kWgs84F);  // first eccentricity squared

Eigen::Vector3d geodetic_to_ecef(double lat_rad, double lon_rad, double h) {
  const double s = std::sin(lat_rad), c = std::cos(lat_rad);
  const double N = kWgs84A / std::sqrt(1.0 - kWgs84E2 * s * s);
  return {(N + h) * c * std::cos(lon_rad), (N + h) * c * std::sin(lon_rad), (N * (1.0 - kWgs84E2) + h) * s};
}

// Fixed-point iteration on the latitude (converges to < 1e-14 rad near the Earth's surface in a
// few steps); the height formula is valid at every latitude.
void ecef_to_geodetic(const Eigen::Vector3d& r, double& lat_rad, double& lon_rad, double& h) {
  lon_rad = std::atan2(r.y(), r.x());
  const double p = std::hypot(r.x(), r.y());
  double lat = std::atan2(r.z(), p * (1.0 - kWgs84E2));
  for (int i = 0; i < 10; ++i) {
    const double s = std::sin(lat);
    const double N = kWgs84A / std::sqrt(1.0 - kWgs84E2 * s * s);
    lat = std::atan2(r.z() + kWgs84E2 * N * s, p);
  }
  const double s = std::sin(lat), c = std::cos(lat);
  h = p * c + r.z() * s - kWgs84A * std::sqrt(1.0 - kWgs84E2 * s * s);
  lat_rad = lat;
}
}  // namespace

WorldGeodesy::WorldGeodesy(const GeoPoint& origin) {
  const double phi = origin.lat * kRadPerDeg, lam = origin.lon * kRadPerDeg;
  ecef0_ = geodetic_to_ecef(phi, lam, origin.alt);
  const double sp = std::sin(phi), cp = std::cos(phi), sl = std::sin(lam), cl = std::cos(lam);
  R_ << -sp * cl, -sp * sl, cp, -sl, cl, 0.0, -cp * cl, -cp * sl, -sp;
}

GeoPoint WorldGeodesy::to_geodetic(const Eigen::Vector3d& ned) const {
  double phi = 0, lam = 0;
  GeoPoint p;
  ecef_to_geodetic(ecef0_ + R_.transpose() * ned, phi, lam, p.alt);
  p.lat = phi / kRadPerDeg;
  p.lon = lam / kRadPerDeg;
  return p;
}

Eigen::Vector3d WorldGeodesy::to_ned(const GeoPoint& p) const {
  return R_ * (geodetic_to_ecef(p.lat * kRadPerDeg, p.lon * kRadPerDeg, p.alt) - ecef0_);
}

// ---------------------------------------------------------------- error models -------------

namespace {
/// Transition factor exp(-dt / tau) of a first-order Gauss-Markov process (0: white).
/// `x` in whole counts of `lsb` (the sensor's resolution; 0: unchanged).
double quantized(double x, double lsb) { return lsb > 0 ? std::round(x / lsb) * lsb : x; }
Eigen::Vector3d quantized(const Eigen::Vector3d& v, double lsb) { return lsb > 0 ? Eigen::Vector3d((v / lsb).array().round() * lsb) : v; }

double gm_phi(double dt, double tau) { return tau > 0 ? std::exp(-std::max(dt, 0.0) / tau) : 0.0; }

// The sky as the receiver's parameters describe it (gnss_sky.hpp); no satellites without gnss_sky.
GnssSkyParams sky_params(const SensorParams& p) {
  GnssSkyParams s;
  s.satellites = p.gnss_sky ? p.gnss_num_sats : 0;
  s.elevation_mask = p.gnss_elevation_mask;
  s.antenna_cutoff = p.gnss_antenna_cutoff;
  s.reacquisition = p.gnss_reacquisition;
  s.pdop_mask = p.gnss_pdop_mask;
  s.horizontal_sigma = p.gnss_h_sigma;
  s.velocity_sigma = p.gnss_vel_noise;
  s.range_tau = p.gnss_tau;
  s.max_acceleration = p.gnss_max_acceleration;
  s.lag_tau = p.gnss_lag_tau;
  return s;
}

/// Specific force at a point r (body) off the CG: f_cg + omega_dot x r + omega x (omega x r).
Eigen::Vector3d specific_force_at(const Truth& t, const Eigen::Vector3d& r) {
  const Eigen::Vector3d w = t.x.segment<3>(P);
  return t.fm.specific_force(t.mass) + t.omega_dot.cross(r) + w.cross(w.cross(r));
}
}  // namespace

Sensors::Sensors(const SensorParams& p, std::uint64_t seed)
    : p_(p),
      seed_(seed),
      origin_(std::make_unique<WorldGeodesy>(GeoPoint{p.origin_lat, p.origin_lon, p.origin_alt})),
      earth_field_(sim::earth_field(p)),
      mount_T_(tern::rotation_from_euler(p.imu_misalignment.x(), p.imu_misalignment.y(), p.imu_misalignment.z()).transpose()),
      gnss_sky_(sky_params(p), seed) {
  reset();
}
Sensors::~Sensors() = default;

Eigen::Vector3d Sensors::uniform3(double range) {
  const double a = uniform(range), b = uniform(range), c = uniform(range);
  return {a, b, c};
}

// I + diag(scale) + off-diagonal cross-axis terms; draws the 3 scales, then the 6 cross terms
// row by row.
Eigen::Matrix3d Sensors::draw_sensor_matrix(double scale_range, double cross_range) {
  Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  M.diagonal() += uniform3(scale_range);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (i != j) M(i, j) = uniform(cross_range);
    }
  }
  return M;
}

// I + E, each element of E uniform in +-range (row by row).
Eigen::Matrix3d Sensors::draw_soft_iron(double range) {
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) S(i, j) += uniform(range);
  }
  return S;
}

// Per-axis N(0, sigma^2): the steady state of the GNSS errors (zero unless gnss_start_steady;
// drawn either way so that the sequence of draws does not depend on the parameters).
Eigen::Vector3d Sensors::draw_gnss_start(const Eigen::Vector3d& sigma) {
  const Eigen::Vector3d e = sigma.cwiseProduct(gauss3());
  return p_.gnss_start_steady ? e : Eigen::Vector3d::Zero();
}

// Draw order (fixed, whatever the parameters): the turn-on biases as before, then the IMU sensor
// matrices, hard and soft iron, the pitot scale and the GNSS starting errors (the accelerometer
// calibration has a stream of its own).
void Sensors::reset() {
  rng_.seed(seed_);
  n_.reset();
  accel_bias_ = uniform3(p_.accel_bias_range);
  gyro_bias_ = uniform3(p_.gyro_bias_range);
  baro_bias_ = uniform(p_.baro_bias_range);
  diff_bias_ = uniform(p_.diff_bias_range);
  accel_M_ = draw_sensor_matrix(p_.accel_scale_range, p_.imu_cross_axis_range);
  gyro_M_ = draw_sensor_matrix(p_.gyro_scale_range, p_.imu_cross_axis_range);
  mag_hard_ = uniform3(p_.mag_hard_iron_range);
  mag_soft_ = draw_soft_iron(p_.mag_soft_iron_range);
  diff_scale_ = 1.0 + uniform(p_.diff_scale_range);
  gnss_gm_ = draw_gnss_start(gnss_sigma());
  gnss_vel_gm_ = draw_gnss_start(Eigen::Vector3d::Constant(p_.gnss_vel_noise));
  mag_gm_.setZero();
  gnss_sky_.reset();
  gnss_time_ = 0.0;
  effects_ = SensorEffects{};
  boot_ = BootCalibration{};
  accel_cal_ = draw_accel_calibration();
}

// ROSflight's Sensors::calibrate_accel on a surface tilted by (roll, pitch): the mean of 1000
// samples at rest (noise sigma / sqrt(1000), the turn-on bias when taken at this power-up) plus
// the firmware's gravity, refused when |.| >= 3.
// Drawn from a stream of its own (seeded from the seed), so that the other draws are the same with
// or without it.
Eigen::Vector3d Sensors::draw_accel_calibration() {
  constexpr int kSamples = 1000;  // src/sensors.cpp: accel_calibration_count_ > 1000
  if (!p_.accel_calibrated_level) return Eigen::Vector3d::Zero();
  Rng rng(seed_ ^ 0xacce1ca1u);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  boost::random::normal_distribution<double> n(0.0, 1.0);
  const double roll = p_.accel_calibration_tilt_range * u(rng), pitch = p_.accel_calibration_tilt_range * u(rng);
  const double n0 = n(rng), n1 = n(rng), n2 = n(rng);
  const Eigen::Vector3d noise = p_.accel_noise / std::sqrt(double{kSamples}) * Eigen::Vector3d(n0, n1, n2);
  const Eigen::Vector3d f_rest = tern::rotation_from_euler(roll, pitch, 0.0).transpose() * Eigen::Vector3d(0.0, 0.0, -kGravity);
  const Eigen::Vector3d bias = p_.accel_calibrated_at_power_up ? accel_bias_ : Eigen::Vector3d::Zero();
  const Eigen::Vector3d offset = accel_M_ * (mount_T_ * f_rest) + bias + noise + Eigen::Vector3d(0.0, 0.0, tern::kStandardGravity);
  return offset.norm() < 3.0 ? offset : Eigen::Vector3d::Zero();
}

void Sensors::calibrated_before_start() {
  if (!p_.calibrate_at_boot) return;
  const Eigen::Vector3d gyro = gyro_bias_ + p_.gyro_noise / std::sqrt(double{BootCalibration::kGyroSamples}) * gauss3();
  const double diff = diff_bias_ + p_.diff_noise / std::sqrt(double{BootCalibration::kCycles}) * gauss();
  boot_.set_done(gyro, diff, standard_pressure(p_.origin_alt) + baro_bias_);
}

Eigen::Vector3d Sensors::gnss_sigma() const { return {p_.gnss_h_sigma, p_.gnss_h_sigma, p_.gnss_v_sigma}; }

// White noise plus motor vibration (independent draws, the vibration scaled by the throttle).
Eigen::Vector3d Sensors::white_and_vibration(double sigma, double vibration_full, double throttle) {
  const Eigen::Vector3d white = sigma * gauss3();
  return white + vibration_full * throttle * gauss3();
}

// Measured = M R_mount^T true + bias + noise, the specific force taken at the IMU's position; the
// accelerometer minus its stored calibration, the gyro minus the FCU's boot calibration when
// calibrate_at_boot.
ImuSample Sensors::imu(const Truth& t, double dt) {
  const double s = std::sqrt(std::max(dt, 0.0));
  accel_bias_ += p_.accel_bias_walk * s * gauss3();
  gyro_bias_ += p_.gyro_bias_walk * s * gauss3();
  const Eigen::Vector3d f = specific_force_at(t, p_.imu_position);
  const Eigen::Vector3d w = t.x.segment<3>(P);
  ImuSample m;
  const Eigen::Vector3d accel =
      accel_M_ * (mount_T_ * f) + accel_bias_ + white_and_vibration(p_.accel_noise, p_.accel_vibration, t.throttle);
  m.accel = quantized(accel, p_.accel_resolution) - accel_cal_;
  m.gyro = quantized(gyro_M_ * (mount_T_ * w) + gyro_bias_ + white_and_vibration(p_.gyro_noise, p_.gyro_vibration, t.throttle),
                     p_.gyro_resolution);
  if (p_.calibrate_at_boot) m.gyro = boot_.gyro(m.gyro);
  m.temperature = quantized(standard_temperature(p_.origin_alt - t.x[PD]), p_.imu_temperature_resolution);
  return m;
}

// field = S (R^T m_ned) + hard + motor + Gauss-Markov + white.
MagSample Sensors::mag(const Truth& t, double dt) {
  const double phi = gm_phi(dt, p_.mag_gm_tau);
  mag_gm_ = phi * mag_gm_ + p_.mag_gm_sigma * std::sqrt(1.0 - phi * phi) * gauss3();
  const Eigen::Vector3d b = attitude(t.x).conjugate() * earth_field_.ned;
  MagSample m;
  m.field = quantized(mag_soft_ * b + mag_hard_ + t.throttle * p_.mag_motor_field + mag_gm_ + p_.mag_noise * gauss3(), p_.mag_resolution);
  return m;
}

// Static pressure + bias + noise + the static port's position error (SensorParams::baro_static_error).
double Sensors::static_port_error(const Truth& t) const {
  const Eigen::Vector3d& v = t.fm.air.v_air;  // relative wind, body FRD
  const double k_y = v.y() > 0.0 ? p_.baro_static_error_yp : p_.baro_static_error_yn;
  return 0.5 * t.rho * (p_.baro_static_error * v.x() * v.x() + k_y * v.y() * v.y() + p_.baro_static_error_z * v.z() * v.z());
}

BaroSample Sensors::baro(const Truth& t, double dt) {
  baro_bias_ += p_.baro_bias_walk * std::sqrt(std::max(dt, 0.0)) * gauss();
  const double h = p_.origin_alt - t.x[PD];
  const double static_error = static_port_error(t);
  effects_.baro_static_error_max = std::max(effects_.baro_static_error_max, std::fabs(static_error));
  BaroSample m;
  m.pressure = quantized(standard_pressure(h) + static_error + baro_bias_ + p_.baro_noise * gauss(), p_.baro_resolution);
  if (p_.calibrate_at_boot) m.pressure = boot_.baro(m.pressure, dt);
  m.temperature = quantized(standard_temperature(h), p_.baro_temperature_resolution);
  return m;
}

// Installation scale times rho u_r^2 / 2, + bias + noise.
DiffPressureSample Sensors::diff_pressure(const Truth& t, double dt) {
  diff_bias_ += p_.diff_bias_walk * std::sqrt(std::max(dt, 0.0)) * gauss();
  const double u_r = t.fm.air.v_air.x();
  DiffPressureSample m;
  m.pressure = quantized(diff_scale_ * 0.5 * t.rho * u_r * u_r + diff_bias_ + p_.diff_noise * gauss(), p_.diff_resolution);
  if (p_.calibrate_at_boot) m.pressure = boot_.diff_pressure(m.pressure, dt);
  m.temperature = quantized(standard_temperature(p_.origin_alt - t.x[PD]), p_.diff_temperature_resolution);
  return m;
}

// Exact discretisation of the first-order Gauss-Markov errors: e <- phi e + sigma sqrt(1 - phi^2) N(0, 1)
// (the steady sigma holds for any dt; tau <= 0 gives white errors).
void Sensors::step_gnss_errors(double dt) {
  const double phi = gm_phi(dt, p_.gnss_tau);
  gnss_gm_ = phi * gnss_gm_ + std::sqrt(1.0 - phi * phi) * gnss_sigma().cwiseProduct(gauss3());
  const double phi_v = gm_phi(dt, p_.gnss_vel_tau);
  gnss_vel_gm_ = phi_v * gnss_vel_gm_ + p_.gnss_vel_noise * std::sqrt(1.0 - phi_v * phi_v) * gauss3();
}

// The antenna's position p + R r + e and velocity R (v + omega x r) + e_v (R: body -> NED), plus
// what the sky the antenna sees adds (gnss_sky.hpp; nothing while it sees the whole sky).
GnssSample Sensors::gnss(const Truth& t, double dt) {
  step_gnss_errors(dt);
  const Eigen::Matrix3d R = attitude(t.x).toRotationMatrix();
  const Eigen::Vector3d r = p_.gnss_antenna_position;
  const Eigen::Vector3d w = t.x.segment<3>(P), v = t.x.segment<3>(U);
  const Eigen::Vector3d vel = R * (v + w.cross(r));
  gnss_time_ += std::max(dt, 0.0);
  const GnssSkyFix sky = gnss_sky_.step(gnss_time_, dt, R * Eigen::Vector3d(0.0, 0.0, -1.0), vel);
  count_effects(sky);
  GnssSample m;
  m.num_sats = gnss_sky_.modelled() ? sky.tracked : p_.gnss_num_sats;
  m.fix = sky.fix;
  if (!sky.fix) return m;
  const GeoPoint fix = origin_->to_geodetic(t.x.segment<3>(PN) + R * r + gnss_gm_ + sky.position_error);
  m.lat = fix.lat;
  m.lon = fix.lon;
  m.alt = fix.alt;
  m.vel_ned = vel + gnss_vel_gm_ + sky.velocity_error;
  m.h_acc = p_.gnss_h_acc * sky.hdop_ratio;
  m.v_acc = p_.gnss_v_acc * sky.vdop_ratio;
  // the receiver's filter sees its residuals grow beyond its platform model: its speed accuracy does too
  m.s_acc = std::hypot(p_.gnss_s_acc * sky.pdop_ratio, sky.velocity_lag);
  m.hdop = sky.hdop;
  m.vdop = sky.vdop;
  return m;
}

void Sensors::count_effects(const GnssSkyFix& sky) {
  ++effects_.gnss_fixes;
  if (gnss_sky_.modelled() && sky.tracked < p_.gnss_num_sats) ++effects_.gnss_degraded;
  if (!sky.fix) ++effects_.gnss_lost;
  effects_.gnss_velocity_lag_max = std::max(effects_.gnss_velocity_lag_max, sky.velocity_lag);
}

msg::Gnss gnss_message(const GnssSample& m, Nanos stamp) {
  msg::Gnss out;
  out.stamp = out.time_of_validity = stamp;
  out.num_sats = static_cast<std::uint8_t>(std::clamp(m.num_sats, 0, 255));
  if (!m.fix) return out;
  out.fix_type = msg::FixType::fix_3d;
  out.lat = m.lat;
  out.lon = m.lon;
  out.alt = m.alt;
  out.vel = m.vel_ned;
  out.h_acc = m.h_acc;
  out.v_acc = m.v_acc;
  out.s_acc = m.s_acc;
  out.hdop = m.hdop;
  out.vdop = m.vdop;
  return out;
}

bool SensorSchedule::dropped(std::int64_t t) const {
  if (!enabled) return true;
  for (const auto& [a, b] : dropouts) {
    if (t >= a && t < b) return true;
  }
  return false;
}

SensorSchedule::Poll SensorSchedule::poll(std::int64_t t) {
  if (period <= 0 || t < next_due) return Poll::idle;
  while (next_due <= t) next_due += period;
  if (dropped(t)) return Poll::dropped;
  return Poll::sample;
}

double SensorSchedule::dt_since_last(std::int64_t t) const {
  return last_sample < 0 ? static_cast<double>(period) * 1e-9 : static_cast<double>(t - last_sample) * 1e-9;
}

}  // namespace tern::sim
