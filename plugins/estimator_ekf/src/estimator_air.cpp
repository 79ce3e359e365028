// Estimator: the barometer and the airspeed sensor (see estimator.hpp).
#include "tern/estimator_ekf/estimator.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "tern/math.hpp"
#include "estimator_fusion.hpp"
#include "tern/atmosphere.hpp"

namespace tern::ekf {

bool Estimator::add_baro(const msg::Baro& m) {
  const bool ok = std::isfinite(m.pressure) && m.pressure > 1000.0 && m.pressure < 120000.0;
  if (!accept(Sensor::baro, m.stamp, ok)) return false;
  const double h = tern::isa_pressure_altitude(m.pressure);
  if (!baro_calibrated_) {
    // Ground calibration, against the origin's altitude: it waits for the origin (a fix that passed
    // the GNSS start-up checks; an unsettled receiver's altitude wanders by metres). Before
    // initialisation the aircraft is at the origin (altitude 0), after it at the estimate's.
    if (!origin_) return true;
    baro_cal_sum_ += h - (initialized_ ? -filter_.x().p.z() : 0.0);
    baro_cal_q_sum_ += dynamic_pressure();
    if (++baro_cal_count_ >= cfg_.baro_calibration_count) {
      baro_offset_ = baro_cal_sum_ / baro_cal_count_;
      baro_.q_datum = baro_cal_q_sum_ / baro_cal_count_;
      baro_calibrated_ = true;
      // the datum: the estimate's altitude, or before initialisation the origin (a GNSS fix)
      baro_datum_var_ = initialized_ ? filter_.P()(idx::p + 2, idx::p + 2) : gnss_error_variance().z();
      push(m.stamp, EventKind::baro_calibrated, Sensor::baro, baro_offset_);
    }
    return true;
  }
  if (!initialized_) return true;
  baro_.dynamic_pressure = dynamic_pressure();
  fuse_robust(Sensor::baro, baro_, BaroAltitude::Vec(h - baro_offset_), valid_at(Sensor::baro, m.stamp), idx::bb, 1);
  return true;
}

bool Estimator::airborne(Nanos stamp) const { return last_Va_stamp_ >= 0 && to_seconds(stamp - last_Va_stamp_) < 0.5; }

double Estimator::dynamic_pressure() const {
  // the pitot's while it reports, else from the estimated airspeed along the body x axis
  if (last_diff_stamp_ >= 0 && !counters_[static_cast<int>(Sensor::diff_pressure)].timed_out) return std::max(last_diff_pressure_, 0.0);
  if (!initialized_) return 0.0;
  const double u_r = filter_.x().air_velocity_body().x();
  return 0.5 * cfg_.rho * u_r * u_r;
}

bool Estimator::add_diff_pressure(const msg::DiffPressure& m) {
  const bool ok = std::isfinite(m.pressure) && m.pressure > -1000.0 && m.pressure < 20000.0;
  if (!accept(Sensor::diff_pressure, m.stamp, ok)) return false;
  last_diff_pressure_ = m.pressure;
  last_diff_stamp_ = m.stamp;
  if (!initialized_) return true;
  const Nanos t_v = valid_at(Sensor::diff_pressure, m.stamp);
  const double Va = pitot_.airspeed(m.pressure);
  fuse(pitot_, PitotAirspeed::Vec(Va), t_v);
  // The aircraft models (side force or zero sideslip, normal force) hold in the air only: below
  // the minimum airspeed (measured, not the estimate, which a wrong wind can lift above it) the
  // wheels' forces would pass for aerodynamic ones. And they take the attitude as known: right after an initialisation in
  // flight (roll and pitch to 20 deg) the side force alone rolled the estimate 5 deg in 0.2 s.
  const Cov& P = filter_.P();
  const bool attitude_known =
      std::max(P(idx::th, idx::th), P(idx::th + 1, idx::th + 1)) <= cfg_.lateral_max_tilt_sigma * cfg_.lateral_max_tilt_sigma;
  if (Va >= cfg_.min_airspeed) {
    last_Va_ = Va;
    last_Va_stamp_ = m.stamp;
  }
  if (Va >= cfg_.min_airspeed && attitude_known) {
    const Vec3 accel = accel_n_ > 0 ? Vec3(accel_sum_ / accel_n_) : Vec3::Zero();
    if (side_force_.k != 0.0 && accel_n_ > 0) {
      fuse(side_force_, SideForce::Vec(accel.y()), t_v);
    } else if (cfg_.use_sideslip) {
      fuse(sideslip_, ZeroSideslip::Vec(0.0), t_v);
    }
    if (normal_force_.k != 0.0 && accel_n_ > 0) {
      normal_force_.q = rate_.y();
      fuse(normal_force_, NormalForce::Vec(accel.z()), t_v);
    }
  }
  accel_sum_.setZero();
  accel_n_ = 0;
  return true;
}

}  // namespace tern::ekf
