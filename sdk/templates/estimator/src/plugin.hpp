// @CLASS@: the tern adapter of ComplementaryFilter (complementary_filter.hpp). Run it with
// `trigger: imu`: it steps on every IMU sample and publishes the state each time.
//
// Ports:  in  imu            msg::Imu (required)
//         in  gnss           msg::Gnss, optional: position, velocity, heading from the course;
//                            fixes other than 3-D are ignored
//         in  diff_pressure  msg::DiffPressure, optional: airspeed
//         in  baro           msg::Baro, optional: air density for the airspeed
//         out state          msg::State; valid once attitude and (with a GNSS) position are
// Parameters: filter constants (complementary_filter.hpp) and the NED origin: origin_mode
// first_fix (the first 3-D fix, as ROSplane's estimator does on the ground) or fixed (origin_*).
// Per-flight state (tern/plugin.hpp): everything a flight changes is in `flight_`, which
// reset() replaces wholesale; a new filter state, counter or flag goes there.
#pragma once

#include <array>
#include <cmath>
#include <optional>
#include <string>

#include "complementary_filter.hpp"
#include "tern/math.hpp"
#include "tern/plugin.hpp"

class @CLASS@ final : public tern::Plugin {
 public:
  void configure() override {
    using tern::ParamSpec;
    declare(imu_, "imu", "accelerometer and gyro, body FRD");
    declare(gnss_, "gnss", "GNSS fix: position, velocity", tern::Need::optional);
    declare(diff_pressure_, "diff_pressure", "pitot differential pressure", tern::Need::optional);
    declare(baro_, "baro", "static pressure and temperature (air density)", tern::Need::optional);
    declare(state_, "state", "estimated state");
    declare_struct(params_);  // FilterParams::describe (complementary_filter.hpp)
    declare(origin_mode_, "origin_mode", "first_fix", ParamSpec("", 0, 0, "NED origin").one_of({"first_fix", "fixed"}));
    declare(origin_lat_, "origin_lat", 40.2463724, ParamSpec("deg", -90.0, 90.0, "origin latitude (origin_mode fixed)"));
    declare(origin_lon_, "origin_lon", -111.6474138, ParamSpec("deg", -180.0, 180.0, "origin longitude (origin_mode fixed)"));
    declare(origin_alt_, "origin_alt", 1387.0, ParamSpec("m", -500.0, 9000.0, "origin altitude MSL (origin_mode fixed)"));
  }

  /// Between flights: as after configure() (no attitude, no position, no origin).
  void reset() override { flight_ = Flight{}; }

  void step(tern::Nanos now) override {
    tern_@NAME@::ComplementaryFilter& filter = flight_.filter;
    filter.set_params(params_);
    if (diff_pressure_.updated()) {
      const double rho = baro_.has_value() ? baro_->pressure / (287.05 * baro_->temperature) : 0.0;
      filter.airspeed(diff_pressure_->pressure, rho);
    }
    if (imu_.updated()) filter.imu(tern::to_seconds(imu_->stamp), imu_->accel, imu_->gyro);
    if (gnss_.updated() && gnss_->fix_type == tern::msg::FixType::fix_3d) {
      const tern::msg::Gnss& g = *gnss_;
      if (!flight_.origin) {
        const bool fixed = origin_mode_() == "fixed";
        flight_.origin = {fixed ? origin_lat_() : g.lat, fixed ? origin_lon_() : g.lon, fixed ? origin_alt_() : g.alt};
      }
      const std::array<double, 3>& o = *flight_.origin;
      filter.gnss(tern_@NAME@::geodetic_to_ned(g.lat, g.lon, g.alt, o[0], o[1], o[2]), g.vel);
    }
    publish(now);
  }

 private:
  void publish(tern::Nanos now) {
    const tern_@NAME@::Estimate& e = flight_.filter.estimate();
    tern::msg::State s;
    s.stamp = now;
    s.p_n = e.p_n;
    s.p_e = e.p_e;
    s.p_d = e.p_d;
    s.v_n = e.v_n;
    s.v_e = e.v_e;
    s.v_d = e.v_d;
    s.phi = e.phi;
    s.theta = e.theta;
    s.psi = e.psi;
    s.quat = tern::quaternion_from_euler(e.phi, e.theta, e.psi);
    const Eigen::Vector3d v_b = tern::rotation_from_euler(e.phi, e.theta, e.psi).transpose() * Eigen::Vector3d(e.v_n, e.v_e, e.v_d);
    s.u = v_b.x();
    s.v = v_b.y();
    s.w = v_b.z();
    s.p = e.p;
    s.q = e.q;
    s.r = e.r;
    s.Va = e.Va;
    s.Vg = std::hypot(e.v_n, e.v_e);
    s.chi = s.Vg > 0.5 ? std::atan2(e.v_e, e.v_n) : e.psi;
    const double V = std::sqrt(e.v_n * e.v_n + e.v_e * e.v_e + e.v_d * e.v_d);
    s.gamma = V > 0.5 ? std::asin(-e.v_d / V) : 0.0;
    const std::array<double, 3> origin = flight_.origin.value_or(std::array<double, 3>{0.0, 0.0, 0.0});
    s.origin_lat = origin[0];
    s.origin_lon = origin[1];
    s.origin_alt = origin[2];
    s.origin_valid = flight_.origin.has_value();
    s.valid = e.attitude_valid && (e.position_valid || !gnss_.connected());
    state_.publish(s);
  }

  tern::Input<tern::msg::Imu> imu_;
  tern::Input<tern::msg::Gnss> gnss_;
  tern::Input<tern::msg::DiffPressure> diff_pressure_;
  tern::Input<tern::msg::Baro> baro_;
  tern::Output<tern::msg::State> state_;
  tern_@NAME@::FilterParams params_;  ///< the filter's parameters' values
  tern::Param<std::string> origin_mode_;
  tern::Param<double> origin_lat_, origin_lon_, origin_alt_;
  /// What a flight changes; reset() replaces it with a fresh one.
  struct Flight {
    tern_@NAME@::ComplementaryFilter filter;       ///< the estimate (step() gives it params_ first)
    std::optional<std::array<double, 3>> origin;  ///< NED origin lat, lon (deg), alt (m MSL); none before
  } flight_;
};
