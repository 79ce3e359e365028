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
#pragma once

#include <array>
#include <cmath>
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

  void start() override { reset(); }
  void reset() override {
    filter_.reset();
    origin_valid_ = false;
  }

  void step(tern::Nanos now) override {
    filter_.set_params(params_);
    if (diff_pressure_.updated()) {
      const double rho = baro_.has_value() ? baro_->pressure / (287.05 * baro_->temperature) : 0.0;
      filter_.airspeed(diff_pressure_->pressure, rho);
    }
    if (imu_.updated()) filter_.imu(tern::to_seconds(imu_->stamp), imu_->accel, imu_->gyro);
    if (gnss_.updated() && gnss_->fix_type == tern::msg::FixType::fix_3d) {
      const tern::msg::Gnss& g = *gnss_;
      if (!origin_valid_) {
        const bool fixed = origin_mode_() == "fixed";
        origin_ = {fixed ? origin_lat_() : g.lat, fixed ? origin_lon_() : g.lon, fixed ? origin_alt_() : g.alt};
        origin_valid_ = true;
      }
      filter_.gnss(tern_@NAME@::geodetic_to_ned(g.lat, g.lon, g.alt, origin_[0], origin_[1], origin_[2]), g.vel);
    }
    publish(now);
  }

 private:
  void publish(tern::Nanos now) {
    const tern_@NAME@::Estimate& e = filter_.estimate();
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
    s.origin_lat = origin_[0];
    s.origin_lon = origin_[1];
    s.origin_alt = origin_[2];
    s.origin_valid = origin_valid_;
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
  tern_@NAME@::ComplementaryFilter filter_;
  std::array<double, 3> origin_{0.0, 0.0, 0.0};
  bool origin_valid_ = false;
};
