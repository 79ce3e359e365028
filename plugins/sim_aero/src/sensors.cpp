// Sensor models (see sensors.hpp).
#include "tern_sim_aero/sensors.hpp"

#include <cmath>

namespace tern::sim {

double standard_temperature(double h) { return 288.15 - 0.0065 * h; }

double standard_pressure(double h) {
  return 101325.0 * std::pow(1.0 - 2.25577e-5 * h, 5.25588);
}

// WGS-84 geodetic <-> ECEF <-> local NED. Written here rather than taken from GeographicLib: that
// library's GNU-unique symbols would keep the plugin loaded after dlclose (hot-swap needs it gone).
namespace {
constexpr double kWgs84A = 6378137.0;                 // semi-major axis, m
constexpr double kWgs84F = 1.0 / 298.257223563;       // flattening
constexpr double kWgs84E2 = kWgs84F * (2.0 - kWgs84F);  // first eccentricity squared
constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

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

struct GeoOrigin::Impl {
  Eigen::Vector3d ecef0;
  Eigen::Matrix3d R;  // ECEF -> NED at the origin
};

GeoOrigin::GeoOrigin(double lat, double lon, double alt) : impl_(std::make_unique<Impl>()) {
  const double phi = lat * kDegToRad, lam = lon * kDegToRad;
  impl_->ecef0 = geodetic_to_ecef(phi, lam, alt);
  const double sp = std::sin(phi), cp = std::cos(phi), sl = std::sin(lam), cl = std::cos(lam);
  impl_->R << -sp * cl, -sp * sl, cp,
              -sl, cl, 0.0,
              -cp * cl, -cp * sl, -sp;
}
GeoOrigin::~GeoOrigin() = default;

void GeoOrigin::to_geodetic(const Eigen::Vector3d& ned, double& lat, double& lon, double& alt) const {
  double phi = 0, lam = 0;
  ecef_to_geodetic(impl_->ecef0 + impl_->R.transpose() * ned, phi, lam, alt);
  lat = phi / kDegToRad;
  lon = lam / kDegToRad;
}

Eigen::Vector3d GeoOrigin::to_ned(double lat, double lon, double alt) const {
  return impl_->R * (geodetic_to_ecef(lat * kDegToRad, lon * kDegToRad, alt) - impl_->ecef0);
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
