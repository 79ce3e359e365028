// Sensor models (see sensors.hpp).
#include "tern_sim_aero/sensors.hpp"

#include <cmath>

#include <GeographicLib/LocalCartesian.hpp>

namespace tern::sim {

double standard_temperature(double h) { return 288.15 - 0.0065 * h; }

double standard_pressure(double h) {
  return 101325.0 * std::pow(1.0 - 2.25577e-5 * h, 5.25588);
}

struct GeoOrigin::Impl {
  GeographicLib::LocalCartesian lc;
};

GeoOrigin::GeoOrigin(double lat, double lon, double alt)
    : impl_(std::make_unique<Impl>(Impl{GeographicLib::LocalCartesian(lat, lon, alt)})) {}
GeoOrigin::~GeoOrigin() = default;

void GeoOrigin::to_geodetic(const Eigen::Vector3d& ned, double& lat, double& lon, double& alt) const {
  impl_->lc.Reverse(ned.y(), ned.x(), -ned.z(), lat, lon, alt);  // ENU
}

Eigen::Vector3d GeoOrigin::to_ned(double lat, double lon, double alt) const {
  double e = 0, n = 0, u = 0;
  impl_->lc.Forward(lat, lon, alt, e, n, u);
  return {n, e, -u};
}

Sensors::Sensors(const SensorParams& p, std::uint64_t seed)
    : p_(p), seed_(seed), origin_(std::make_unique<GeoOrigin>(p.origin_lat, p.origin_lon, p.origin_alt)) {
  reset();
}
Sensors::~Sensors() = default;

void Sensors::reset() {
  rng_.seed(seed_);
  n_.reset();
  accel_bias_ = Eigen::Vector3d(uniform(p_.accel_bias_range), uniform(p_.accel_bias_range),
                                uniform(p_.accel_bias_range));
  gyro_bias_ = Eigen::Vector3d(uniform(p_.gyro_bias_range), uniform(p_.gyro_bias_range),
                               uniform(p_.gyro_bias_range));
  baro_bias_ = uniform(p_.baro_bias_range);
  diff_bias_ = uniform(p_.diff_bias_range);
  mag_gm_.setZero();
  gnss_gm_.setZero();
}

ImuSample Sensors::imu(const Truth& t, double dt) {
  const double s = std::sqrt(std::max(dt, 0.0));
  accel_bias_ += p_.accel_bias_walk * s * gauss3();
  gyro_bias_ += p_.gyro_bias_walk * s * gauss3();
  ImuSample m;
  m.accel = t.fm.specific_force(t.mass) + accel_bias_ + p_.accel_noise * gauss3();
  m.gyro = t.x.segment<3>(P) + gyro_bias_ + p_.gyro_noise * gauss3();
  m.temperature = standard_temperature(p_.origin_alt - t.x[PD]);
  return m;
}

MagSample Sensors::mag(const Truth& t, double dt) {
  const double phi = p_.mag_gm_tau > 0 ? std::exp(-dt / p_.mag_gm_tau) : 0.0;
  mag_gm_ = phi * mag_gm_ + p_.mag_gm_sigma * std::sqrt(1.0 - phi * phi) * gauss3();
  const double I = p_.mag_inclination, D = p_.mag_declination;
  const Eigen::Vector3d m_ned = p_.mag_intensity * Eigen::Vector3d(std::cos(I) * std::cos(D),
                                                                   std::cos(I) * std::sin(D), std::sin(I));
  MagSample m;
  m.field = attitude(t.x).conjugate() * m_ned + mag_gm_ + p_.mag_noise * gauss3();
  return m;
}

BaroSample Sensors::baro(const Truth& t, double dt) {
  baro_bias_ += p_.baro_bias_walk * std::sqrt(std::max(dt, 0.0)) * gauss();
  const double h = p_.origin_alt - t.x[PD];
  BaroSample m;
  m.pressure = standard_pressure(h) + baro_bias_ + p_.baro_noise * gauss();
  m.temperature = standard_temperature(h);
  return m;
}

DiffPressureSample Sensors::diff_pressure(const Truth& t, double dt) {
  diff_bias_ += p_.diff_bias_walk * std::sqrt(std::max(dt, 0.0)) * gauss();
  const double u_r = t.fm.air.v_air.x();
  DiffPressureSample m;
  m.pressure = 0.5 * t.rho * u_r * u_r + diff_bias_ + p_.diff_noise * gauss();
  m.temperature = standard_temperature(p_.origin_alt - t.x[PD]);
  return m;
}

GnssSample Sensors::gnss(const Truth& t, double dt) {
  // Book sec. 7.5: nu[n+1] = exp(-k Ts) nu[n] + eta, with eta scaled to the sample interval.
  const double phi = std::exp(-p_.gnss_k * dt);
  const double s = std::sqrt(std::max(dt, 0.0));
  const Eigen::Vector3d g = gauss3();
  gnss_gm_ = phi * gnss_gm_ + s * Eigen::Vector3d(p_.gnss_h_noise * g.x(), p_.gnss_h_noise * g.y(),
                                                   p_.gnss_v_noise * g.z());
  GnssSample m;
  origin_->to_geodetic(t.x.segment<3>(PN) + gnss_gm_, m.lat, m.lon, m.alt);
  m.vel_ned = attitude(t.x) * Eigen::Vector3d(t.x.segment<3>(U)) + p_.gnss_vel_noise * gauss3();
  m.h_acc = p_.gnss_h_acc;
  m.v_acc = p_.gnss_v_acc;
  m.s_acc = p_.gnss_s_acc;
  m.num_sats = p_.gnss_num_sats;
  m.fix = true;
  return m;
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
