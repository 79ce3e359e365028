// estimator_ekf plugin class (header so that tests can instantiate it): binds tern::ekf::Estimator to ports and parameters.
//
// Inputs: imu (required), gnss, baro, diff_pressure, mag, actuators (optional).
// Outputs: state (msg::State), every output_decimation-th IMU sample, and on every step while the
// IMU is silent (status invalid); innovations (msg::Innovations) every innovations_period.
// Schedule it with `rate:` at the IMU's rate rather than `trigger: imu`: only a plugin stepped
// by the clock notices that the IMU went silent.
// Every figure of EstimatorConfig is a parameter (table below); changes apply from the next step.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include "tern/estimator_ekf/estimator.hpp"
#include "tern/math.hpp"
#include "tern/plugin.hpp"

namespace tern::ekf::plugin {

using tern::ekf::EstimatorConfig;

struct RealParam {
  const char* name;
  const char* unit;
  double min, max;
  const char* description;
  double& (*field)(EstimatorConfig&);
};

#define TERN_EKF_FIELD(expr) [](EstimatorConfig& c) -> double& { return c.expr; }



inline const RealParam kReal[] = {
    {"gravity", "m/s^2", 9.0, 10.5, "gravitational acceleration", TERN_EKF_FIELD(gravity)},
    {"rho", "kg/m^3", 0.3, 1.5, "air density for the differential pressure", TERN_EKF_FIELD(rho)},
    {"accel_noise", "m/s^2", 1e-4, 10.0, "accelerometer white noise, 1 sigma per IMU sample",
     TERN_EKF_FIELD(process.accel)},
    {"gyro_noise", "rad/s", 1e-6, 1.0, "gyro white noise, 1 sigma per IMU sample",
     TERN_EKF_FIELD(process.gyro)},
    {"gyro_scale", "", 0.0, 0.5, "gyro scale-factor and cross-axis error, fraction of the rate",
     TERN_EKF_FIELD(process.gyro_scale)},
    {"maneuver_time", "s", 0.0, 60.0, "how long a rate is held: correlation time of the gyro scale error",
     TERN_EKF_FIELD(process.maneuver_time)},
    {"gyro_bias_walk", "rad/s/sqrt(s)", 0.0, 1.0, "gyro-bias random walk",
     TERN_EKF_FIELD(process.gyro_bias_walk)},
    {"accel_bias_walk", "m/s^2/sqrt(s)", 0.0, 10.0, "accelerometer-bias random walk",
     TERN_EKF_FIELD(process.accel_bias_walk)},
    {"wind_walk", "m/s/sqrt(s)", 0.0, 10.0, "horizontal-wind random walk",
     TERN_EKF_FIELD(process.wind_walk)},
    {"baro_bias_walk", "m/sqrt(s)", 0.0, 10.0, "barometer-bias random walk",
     TERN_EKF_FIELD(process.baro_bias_walk)},
    {"pos_process_noise", "m/sqrt(s)", 0.0, 10.0, "extra position random walk (model error)",
     TERN_EKF_FIELD(process.position)},
    {"gnss_error_walk_h", "m/sqrt(s)", 0.0, 100.0,
     "driving noise of the GNSS horizontal position error (Gauss-Markov state)",
     TERN_EKF_FIELD(process.gnss_error_walk_h)},
    {"gnss_error_walk_v", "m/sqrt(s)", 0.0, 100.0,
     "driving noise of the GNSS vertical position error (Gauss-Markov state)",
     TERN_EKF_FIELD(process.gnss_error_walk_v)},
    {"gnss_error_rate", "1/s", 0.0, 10.0,
     "Gauss-Markov rate k of the GNSS position error (ROSflight k_gnss 1/1100)",
     TERN_EKF_FIELD(process.gnss_error_k)},
    {"init_gnss_error_sigma", "m", 1e-3, 100.0, "initial GNSS position-error uncertainty, 1 sigma",
     TERN_EKF_FIELD(init_gnss_error_sigma)},
    {"gnss_pos_noise_h", "m", 1e-3, 100.0, "white part of the GNSS horizontal position noise, 1 sigma",
     TERN_EKF_FIELD(gnss_pos_sigma_h)},
    {"gnss_pos_noise_v", "m", 1e-3, 100.0, "white part of the GNSS altitude noise, 1 sigma",
     TERN_EKF_FIELD(gnss_pos_sigma_v)},
    {"gnss_vel_noise_h", "m/s", 1e-4, 10.0, "GNSS horizontal velocity noise, 1 sigma",
     TERN_EKF_FIELD(gnss_vel_sigma_h)},
    {"gnss_vel_noise_v", "m/s", 1e-4, 10.0, "GNSS vertical velocity noise, 1 sigma",
     TERN_EKF_FIELD(gnss_vel_sigma_v)},
    {"gnss_pos_gate", "", 0.0, 1e6, "chi-square gate of GNSS position (3 dof; 0: off)",
     TERN_EKF_FIELD(gnss_pos_gate)},
    {"gnss_vel_gate", "", 0.0, 1e6, "chi-square gate of GNSS velocity (3 dof; 0: off)",
     TERN_EKF_FIELD(gnss_vel_gate)},
    {"gnss_reset_time", "s", 0.5, 600.0,
     "continuous GNSS position rejection after which the state is reset to GNSS",
     TERN_EKF_FIELD(gnss_reset_time)},
    {"gnss_recovery_time", "s", 0.0, 60.0,
     "after a GNSS time-out, the published position takes the correction with this time constant (0: at once)",
     TERN_EKF_FIELD(gnss_recovery_time)},
    {"mag_declination", "rad", -tern::kPi, tern::kPi, "magnetic declination, east of true north",
     TERN_EKF_FIELD(mag_declination)},
    {"mag_inclination", "rad", -tern::kPi / 2, tern::kPi / 2, "magnetic inclination, down from horizontal",
     TERN_EKF_FIELD(mag_inclination)},
    {"mag_field_strength", "T", 1e-6, 1e-3, "total magnetic field intensity",
     TERN_EKF_FIELD(mag_field_strength)},
    {"mag_noise", "T", 1e-9, 1e-4, "magnetometer noise per axis, 1 sigma", TERN_EKF_FIELD(mag_sigma)},
    {"mag_gate", "", 0.0, 1e6, "chi-square gate of the 3-axis magnetometer update (3 dof; 0: off)",
     TERN_EKF_FIELD(mag_gate)},
    {"mag_heading_gate", "", 0.0, 1e6, "chi-square gate of the magnetic heading update (1 dof; 0: off)",
     TERN_EKF_FIELD(mag_heading_gate)},
    {"mag_init_wait", "s", 0.0, 60.0,
     "time to wait for a magnetometer sample after the origin is set before initialising without",
     TERN_EKF_FIELD(mag_init_wait)},
    {"mag_reset_time", "s", 0.1, 600.0,
     "continuous magnetic-heading rejection after which yaw is reset to the magnetometer",
     TERN_EKF_FIELD(mag_reset_time)},
    {"mag_reset_window", "s", 0.0, 1e6,
     "yaw resets to the magnetometer only within this long after initialisation (0: never)",
     TERN_EKF_FIELD(mag_reset_window)},
    {"baro_noise", "Pa", 1e-3, 1000.0, "static-pressure noise, 1 sigma", TERN_EKF_FIELD(baro_sigma)},
    {"baro_gate", "", 0.0, 1e6, "chi-square gate of the barometric altitude (1 dof; 0: off)",
     TERN_EKF_FIELD(baro_gate)},
    {"diff_pressure_noise", "Pa", 1e-3, 100.0, "differential-pressure noise, 1 sigma",
     TERN_EKF_FIELD(diff_pressure_sigma)},
    {"airspeed_gust_sigma", "m/s", 0.0, 20.0,
     "turbulence along body x the wind state does not follow (adds rho u_r sigma to the pitot noise)",
     TERN_EKF_FIELD(airspeed_gust_sigma)},
    {"diff_pressure_gate", "", 0.0, 1e6, "chi-square gate of the differential pressure (1 dof; 0: off)",
     TERN_EKF_FIELD(diff_pressure_gate)},
    {"min_airspeed", "m/s", 0.0, 100.0,
     "airspeed below which the pitot and zero-sideslip updates are skipped",
     TERN_EKF_FIELD(min_airspeed)},
    {"sideslip_noise", "m/s", 1e-3, 100.0, "zero-sideslip pseudo-measurement noise (body-y air velocity)",
     TERN_EKF_FIELD(sideslip_sigma)},
    {"sideslip_gate", "", 0.0, 1e6, "chi-square gate of the zero-sideslip update (1 dof; 0: off)",
     TERN_EKF_FIELD(sideslip_gate)},
    {"side_force_noise", "m/s^2", 1e-3, 100.0,
     "side-force update noise: body-y accelerometer (averaged between pitot samples) against the aircraft's C_Y model",
     TERN_EKF_FIELD(side_force_sigma)},
    {"side_force_gate", "", 0.0, 1e6, "chi-square gate of the side-force update (1 dof; 0: off)",
     TERN_EKF_FIELD(side_force_gate)},
    {"wing_S", "m^2", 0.0, 100.0, "wing area for the side-force model (default: the aircraft file's; 0: side force off)",
     TERN_EKF_FIELD(wing_S)},
    {"mass", "kg", 0.0, 1000.0, "aircraft mass for the side-force model (default: the aircraft file's; 0: off)",
     TERN_EKF_FIELD(mass)},
    {"C_Y_0", "", -10.0, 10.0, "side-force coefficient at zero sideslip (default: the aircraft file's)",
     TERN_EKF_FIELD(C_Y_0)},
    {"C_Y_beta", "1/rad", -20.0, 20.0, "side-force derivative in sideslip (default: the aircraft file's; 0: off)",
     TERN_EKF_FIELD(C_Y_beta)},
    {"C_Y_delta_a", "1/rad", -10.0, 10.0, "side force per aileron deflection (default: the aircraft file's)",
     TERN_EKF_FIELD(C_Y_delta_a)},
    {"C_Y_delta_r", "1/rad", -10.0, 10.0, "side force per rudder deflection (default: the aircraft file's)",
     TERN_EKF_FIELD(C_Y_delta_r)},
    {"init_average_time", "s", 0.0, 10.0, "time constant of the accel/gyro averages before initialisation",
     TERN_EKF_FIELD(init_average_time)},
    {"init_tilt_sigma", "rad", 1e-4, 3.0, "initial roll/pitch uncertainty, 1 sigma",
     TERN_EKF_FIELD(init_tilt_sigma)},
    {"init_yaw_sigma", "rad", 1e-4, 3.2, "initial yaw uncertainty with a magnetometer, 1 sigma",
     TERN_EKF_FIELD(init_yaw_sigma)},
    {"init_gyro_bias_sigma", "rad/s", 1e-6, 1.0, "initial gyro-bias uncertainty, 1 sigma",
     TERN_EKF_FIELD(init_gyro_bias_sigma)},
    {"init_accel_bias_sigma", "m/s^2", 1e-6, 10.0, "initial accelerometer-bias uncertainty, 1 sigma",
     TERN_EKF_FIELD(init_accel_bias_sigma)},
    {"init_wind_sigma_airdata", "m/s", 1e-3, 50.0,
     "initial wind uncertainty when initialised in flight from GNSS velocity and pitot airspeed",
     TERN_EKF_FIELD(init_wind_sigma_airdata)},
    {"init_wind_sigma", "m/s", 1e-3, 50.0, "initial wind uncertainty without air data, 1 sigma",
     TERN_EKF_FIELD(init_wind_sigma)},
    {"init_baro_bias_sigma", "m", 1e-3, 1000.0, "initial barometer-bias uncertainty, 1 sigma",
     TERN_EKF_FIELD(init_baro_bias_sigma)},
    {"accel_max", "m/s^2", 1.0, 2000.0, "accelerometer samples beyond this (any axis) are rejected",
     TERN_EKF_FIELD(accel_max)},
    {"gyro_max", "rad/s", 0.1, 100.0, "gyro samples beyond this (any axis) are rejected",
     TERN_EKF_FIELD(gyro_max)},
    {"imu_max_dt", "s", 1e-4, 1.0, "longest IMU interval propagated in one step (longer gaps are clamped)",
     TERN_EKF_FIELD(imu_max_dt)},
    {"imu_timeout", "s", 1e-3, 60.0, "IMU silence reported as a time-out", TERN_EKF_FIELD(timeout[0])},
    {"gnss_timeout", "s", 1e-3, 60.0, "GNSS silence (or no fix) reported as a time-out",
     TERN_EKF_FIELD(timeout[1])},
    {"baro_timeout", "s", 1e-3, 60.0, "barometer silence reported as a time-out", TERN_EKF_FIELD(timeout[2])},
    {"diff_pressure_timeout", "s", 1e-3, 60.0, "differential-pressure silence reported as a time-out",
     TERN_EKF_FIELD(timeout[3])},
    {"mag_timeout", "s", 1e-3, 60.0, "magnetometer silence reported as a time-out", TERN_EKF_FIELD(timeout[4])},
    {"gnss_delay", "s", 0.0, 0.5,
     "GNSS delay subtracted from each fix's time of validity (0 when the driver gives the receiver's epoch, as "
     "sim_aero does; over ROSflight's link the receiver's output latency, ~0.1 s for a u-blox M8N at 10 Hz)",
     TERN_EKF_FIELD(delay[1])},
    {"baro_delay", "s", 0.0, 0.5, "barometer sample delay (its filter's group delay)", TERN_EKF_FIELD(delay[2])},
    {"diff_pressure_delay", "s", 0.0, 0.5, "differential-pressure sample delay (tubing and filter)",
     TERN_EKF_FIELD(delay[3])},
    {"mag_delay", "s", 0.0, 0.5, "magnetometer sample delay", TERN_EKF_FIELD(delay[4])},
    {"reset_min_interval", "s", 0.0, 3600.0,
     "at most one GNSS reset per this long (covariance inflation carries the rest)",
     TERN_EKF_FIELD(reset_min_interval)},
    {"gnss_fault_distance", "m", 1.0, 1e6,
     "a GNSS innovation beyond this resets the position regardless of reset_min_interval",
     TERN_EKF_FIELD(gnss_fault_distance)},
    {"imu_reinit_gap", "s", 0.05, 60.0,
     "IMU silence after which the attitude counts as lost and the filter re-initialises in flight",
     TERN_EKF_FIELD(imu_reinit_gap)},
    {"max_position_sigma", "m", 1.0, 1e6, "horizontal position 1 sigma beyond which the state is invalid",
     TERN_EKF_FIELD(max_position_sigma)},
    {"max_tilt_sigma", "rad", 0.01, 3.2, "roll/pitch 1 sigma beyond which the state is invalid",
     TERN_EKF_FIELD(max_tilt_sigma)},
};
#undef TERN_EKF_FIELD
constexpr std::size_t kRealCount = sizeof(kReal) / sizeof(kReal[0]);

class EstimatorEkf final : public tern::Plugin {
 public:
  void configure() override {
    using tern::Need;
    declare(imu_, "imu", "IMU samples; each one propagates the filter (use trigger: imu)");
    declare(gnss_, "gnss", "GNSS solutions: origin, position and velocity updates", Need::optional);
    declare(baro_, "baro", "static pressure: altitude updates after the ground calibration", Need::optional);
    declare(diff_, "diff_pressure", "pitot differential pressure: airspeed and zero-sideslip updates",
            Need::optional);
    declare(mag_, "mag", "magnetometer: attitude (heading) updates", Need::optional);
    declare(actuators_, "actuators", "surface deflections for the side-force model (delta_a, delta_r)",
            Need::optional);
    declare(state_, "state", "the estimate; status: ok, degraded (which sensor) or invalid");
    declare(innovations_, "innovations",
            "largest innovation test ratio (NIS / gate) of each measurement over innovations_period");

    const EstimatorConfig def;
    EstimatorConfig scratch = def;
    // Defaults from the mission's aircraft file when it has them: the air density
    // (environment: rho:, so that the pitot model matches the simulator's; else ROSplane's
    // 1.225 kg/m^3) and, for the side-force model, mass, wing area and the C_Y derivatives.
    if (!context().describing() && !context().aircraft_file().empty()) read_aircraft(context().aircraft_file().string(), scratch);
    for (std::size_t i = 0; i < kRealCount; ++i) {
      const RealParam& d = kReal[i];
      declare(reals_[i], d.name, d.field(scratch), tern::ParamSpec(d.unit, d.min, d.max, d.description));
      reals_[i].on_change([this](const double&) { dirty_ = true; });
    }
    declare(min_fix_type_, "min_gnss_fix_type", std::int64_t{def.min_fix_type},
            tern::ParamSpec("", 2, 3, "minimum GNSS fix type used (2: 2-D, 3: 3-D)"));
    declare(baro_cal_count_, "baro_calibration_count", std::int64_t{def.baro_calibration_count},
            tern::ParamSpec("", 1, 100000, "barometer samples averaged for the ground calibration"));
    declare(init_min_imu_, "init_min_imu_samples", std::int64_t{def.init_min_imu_samples},
            tern::ParamSpec("", 1, 100000, "IMU samples averaged before initialisation"));
    declare(decimation_, "output_decimation", std::int64_t{1},
            tern::ParamSpec("", 1, 1000, "publish state every n-th IMU sample"));
    declare(inflate_after_, "inflate_after", std::int64_t{def.inflate_after},
            tern::ParamSpec("", 1, 1000,
                            "consecutive GNSS or baro rejections after which the covariance of the states "
                            "they measure is inflated (instead of a reset)"));
    declare(innovations_period_, "innovations_period", 0.1,
            tern::ParamSpec("s", 0.0025, 10.0, "period of the innovations output"));
    declare_vector(gnss_antenna_, "gnss_antenna_position", def.gnss_antenna, "m", 10.0,
                   "GNSS antenna position from the CG, body FRD (x forward, y right, z down), measured on the aircraft");
    declare_vector(imu_position_, "imu_position", def.imu_position, "m", 10.0,
                   "IMU position from the CG, body FRD, measured on the aircraft");
    declare_vector(imu_mount_, "imu_mount", def.imu_mount, "rad", tern::kPi,
                   "IMU axes relative to the body axes: roll, pitch, yaw (3-2-1); v_body = R(imu_mount) v_imu");
    declare_vector(imu_mount_sigma_, "imu_mount_sigma", def.imu_mount_sigma, "rad", 1.0,
                   "uncertainty of imu_mount per body axis, 1 sigma: added to the published attitude covariance");
    declare(mag_heading_only_, "mag_heading_only", def.mag_heading_only,
            tern::ParamSpec("", 0, 1,
                            "magnetometer as tilt-compensated heading (true) or 3-axis direction (false)"));
    mag_heading_only_.on_change([this](const bool&) { dirty_ = true; });
    declare(use_gnss_accuracy_, "use_gnss_accuracy", def.use_gnss_accuracy,
            tern::ParamSpec("", 0, 1,
                            "use the receiver's reported h_acc/v_acc (steady sigma of the GNSS error) and s_acc "
                            "(velocity noise) where larger than gnss_error_walk_*, gnss_vel_noise_*"));
    use_gnss_accuracy_.on_change([this](const bool&) { dirty_ = true; });
    declare(use_sideslip_, "use_sideslip", def.use_sideslip,
            tern::ParamSpec("", 0, 1, "apply the zero-sideslip pseudo-measurement (when the side-force model is off)"));
    declare(use_side_force_, "use_side_force", def.use_side_force,
            tern::ParamSpec("", 0, 1,
                            "measure sideslip from the body-y accelerometer and the aircraft's C_Y model "
                            "(needs wing_S, mass, C_Y_beta; else zero-sideslip)"));
    use_side_force_.on_change([this](const bool&) { dirty_ = true; });
    min_fix_type_.on_change([this](const std::int64_t&) { dirty_ = true; });
    baro_cal_count_.on_change([this](const std::int64_t&) { dirty_ = true; });
    init_min_imu_.on_change([this](const std::int64_t&) { dirty_ = true; });
    inflate_after_.on_change([this](const std::int64_t&) { dirty_ = true; });
    use_sideslip_.on_change([this](const bool&) { dirty_ = true; });
    estimator_.set_config(make_config());
  }

  /// Declares a 3-vector parameter with its default from the config.
  void declare_vector(tern::Param<std::vector<double>>& p, const char* name, const tern::ekf::Vec3& def,
                      const char* unit, double limit, const char* description) {
    declare(p, name, std::vector<double>{def.x(), def.y(), def.z()},
            tern::ParamSpec(unit, -limit, limit, description).of_size(3));
    p.on_change([this](const std::vector<double>&) { dirty_ = true; });
  }

  void start() override {
    estimator_.set_config(make_config());
    estimator_.expect_mag(mag_.connected());
    estimator_.expect(Sensor::gnss, gnss_.connected());
    estimator_.expect(Sensor::baro, baro_.connected());
    estimator_.expect(Sensor::diff_pressure, diff_.connected());
    estimator_.expect(Sensor::mag, mag_.connected());
    ticks_ = 0;
  }

  void step(tern::Nanos now) override {
    if (dirty_) {
      estimator_.set_config(make_config());
      dirty_ = false;
    }
    const bool imu_new = imu_.updated();
    if (imu_new) estimator_.add_imu(*imu_);
    if (gnss_.updated()) estimator_.add_gnss(*gnss_);
    if (baro_.updated()) estimator_.add_baro(*baro_);
    if (diff_.updated()) estimator_.add_diff_pressure(*diff_);
    if (mag_.updated()) estimator_.add_mag(*mag_);
    if (actuators_.updated()) estimator_.set_controls(actuators_->delta_a, actuators_->delta_r);
    // On the host's clock: with `rate:` scheduling a silent IMU times out here.
    estimator_.check_timeouts(now);
    if (estimator_.has_events()) {
      for (const auto& e : estimator_.take_events()) {
        if (e.kind == tern::ekf::EventKind::sensor_timeout || e.kind == tern::ekf::EventKind::gnss_reset ||
            e.kind == tern::ekf::EventKind::filter_reset || e.kind == tern::ekf::EventKind::mag_reset || e.kind == tern::ekf::EventKind::first_invalid ||
            e.kind == tern::ekf::EventKind::imu_gap)
          log().warn("t={:.3f} s: {}", tern::to_seconds(e.stamp), tern::ekf::describe(e));
        else
          log().info("t={:.3f} s: {}", tern::to_seconds(e.stamp), tern::ekf::describe(e));
      }
    }
    const bool imu_silent = estimator_.counters(tern::ekf::Sensor::imu).timed_out;
    if ((imu_new || imu_silent) && (ticks_++ % decimation_()) == 0) {
      estimator_.fill_state(out_);
      if (imu_silent) out_.stamp = now;  // the invalid state is news of now
      state_.publish(out_);
    }
    if (now - last_innovations_ >= tern::from_seconds(innovations_period_())) {
      innovations_out_ = estimator_.take_innovations(now);
      innovations_.publish(innovations_out_);
      last_innovations_ = now;
    }
  }

  void reset() override {
    estimator_.reset();
    ticks_ = 0;
    last_innovations_ = std::numeric_limits<tern::Nanos>::min() / 2;
  }

  std::vector<std::pair<std::string, double>> summary() const override {
    using tern::ekf::Sensor;
    std::vector<std::pair<std::string, double>> s;
    for (int i = 0; i < tern::ekf::kSensorCount; ++i) {
      const auto sensor = static_cast<Sensor>(i);
      const auto& c = estimator_.counters(sensor);
      const std::string n = tern::ekf::sensor_name(sensor);
      s.emplace_back(n + "_received", static_cast<double>(c.received));
      s.emplace_back(n + "_invalid", static_cast<double>(c.invalid));
      s.emplace_back(n + "_timeouts", static_cast<double>(c.timeouts));
    }
    const auto rej = [&](const char* name, const tern::ekf::UpdateStats& st) {
      s.emplace_back(std::string(name) + "_accepted", static_cast<double>(st.accepted));
      s.emplace_back(std::string(name) + "_rejected", static_cast<double>(st.rejected));
      if (st.nis_count > 0) s.emplace_back(std::string(name) + "_mean_nis", st.mean_nis());
    };
    rej("gnss_pos", estimator_.gnss_position_model().stats);
    rej("gnss_vel", estimator_.gnss_velocity_model().stats);
    rej("mag", estimator_.mag_model().stats);
    rej("mag_heading", estimator_.mag_heading_model().stats);
    rej("baro", estimator_.baro_model().stats);
    rej("diff_pressure", estimator_.diff_pressure_model().stats);
    rej("sideslip", estimator_.sideslip_model().stats);
    rej("side_force", estimator_.side_force_model().stats);
    s.emplace_back("gnss_resets", static_cast<double>(estimator_.gnss_resets()));
    s.emplace_back("mag_resets", static_cast<double>(estimator_.mag_resets()));
    s.emplace_back("filter_resets", static_cast<double>(estimator_.filter_resets()));
    s.emplace_back("inflations", static_cast<double>(estimator_.inflations()));
    return s;
  }

  /// For tests in the same process: the estimator behind the ports.
  const tern::ekf::Estimator& estimator() const { return estimator_; }

 private:
  /// Reads what the estimator can use from an aircraft file, in tern's format (mass, wing: S,
  /// environment: rho, aero: C_Y_*) or ROSflight's (`<node>: ros__parameters:` with mass,
  /// wing_s, rho, C_Y_*). Missing keys keep the defaults.
  static void read_aircraft(const std::string& path, EstimatorConfig& c) {
    try {
      const YAML::Node ac = YAML::LoadFile(path);
      const auto take = [&](const YAML::Node& n, double& dst) {
        if (n && n.IsScalar()) dst = n.as<double>();
      };
      if (ac["environment"]) take(ac["environment"]["rho"], c.rho);
      take(ac["mass"], c.mass);
      if (ac["wing"]) take(ac["wing"]["S"], c.wing_S);
      if (const YAML::Node aero = ac["aero"]) {
        take(aero["C_Y_0"], c.C_Y_0);
        take(aero["C_Y_beta"], c.C_Y_beta);
        take(aero["C_Y_delta_a"], c.C_Y_delta_a);
        take(aero["C_Y_delta_r"], c.C_Y_delta_r);
      }
      if (ac.IsMap())
        for (const auto& node : ac) {
          const YAML::Node rp = node.second.IsMap() ? node.second["ros__parameters"] : YAML::Node();
          if (!rp || !rp.IsMap()) continue;
          take(rp["rho"], c.rho);
          take(rp["mass"], c.mass);
          take(rp["wing_s"], c.wing_S);
          take(rp["C_Y_0"], c.C_Y_0);
          take(rp["C_Y_O"], c.C_Y_0);  // ROSflight spells it with a letter O
          take(rp["C_Y_beta"], c.C_Y_beta);
          take(rp["C_Y_delta_a"], c.C_Y_delta_a);
          take(rp["C_Y_delta_r"], c.C_Y_delta_r);
        }
    } catch (const YAML::Exception& e) {
      throw std::runtime_error(path + ": cannot read the aircraft's rho, mass, wing area or C_Y_*: " + e.what());
    }
  }

  EstimatorConfig make_config() {
    EstimatorConfig c;
    for (std::size_t i = 0; i < kRealCount; ++i) kReal[i].field(c) = reals_[i]();
    c.min_fix_type = static_cast<int>(min_fix_type_());
    c.baro_calibration_count = static_cast<int>(baro_cal_count_());
    c.init_min_imu_samples = static_cast<int>(init_min_imu_());
    c.use_sideslip = use_sideslip_();
    c.use_side_force = use_side_force_();
    c.mag_heading_only = mag_heading_only_();
    c.inflate_after = static_cast<int>(inflate_after_());
    c.use_gnss_accuracy = use_gnss_accuracy_();
    const auto vec3 = [](const std::vector<double>& v) { return tern::ekf::Vec3(v[0], v[1], v[2]); };
    c.gnss_antenna = vec3(gnss_antenna_());
    c.imu_position = vec3(imu_position_());
    c.imu_mount = vec3(imu_mount_());
    c.imu_mount_sigma = vec3(imu_mount_sigma_());
    return c;
  }

  tern::Input<tern::msg::Imu> imu_;
  tern::Input<tern::msg::Gnss> gnss_;
  tern::Input<tern::msg::Baro> baro_;
  tern::Input<tern::msg::DiffPressure> diff_;
  tern::Input<tern::msg::Mag> mag_;
  tern::Input<tern::msg::Actuators> actuators_;
  tern::Output<tern::msg::State> state_;
  tern::Output<tern::msg::Innovations> innovations_;
  std::array<tern::Param<double>, kRealCount> reals_;
  tern::Param<std::int64_t> min_fix_type_, baro_cal_count_, init_min_imu_, decimation_, inflate_after_;
  tern::Param<double> innovations_period_;
  tern::Param<std::vector<double>> gnss_antenna_, imu_position_, imu_mount_, imu_mount_sigma_;
  tern::Param<bool> use_sideslip_, use_side_force_, mag_heading_only_, use_gnss_accuracy_;
  tern::ekf::Estimator estimator_;
  tern::msg::State out_;
  tern::msg::Innovations innovations_out_;
  tern::Nanos last_innovations_ = std::numeric_limits<tern::Nanos>::min() / 2;
  std::uint64_t ticks_ = 0;
  bool dirty_ = false;
};

}  // namespace tern::ekf::plugin
