// sensor_params.hpp: sim_aero's parameters of the sensor and actuator models, one row each (name,
// unit, range, description, the field it sets). The plugin declares every row with the chosen
// `sensor_profile`'s value as its default (profiles.hpp), so a mission config sets a profile and
// overrides single figures. Read at start: a change in flight applies at the next flight.
#pragma once

#include <Eigen/Core>

#include "tern_sim_aero/sensors.hpp"
#include "tern_sim_aero/simulator.hpp"

namespace tern::sim_aero {

template <class Struct, class Field>
struct FieldRow {
  const char* name;
  const char* unit;
  double min, max;
  const char* description;
  Field Struct::*field;
};
using SensorReal = FieldRow<sim::SensorParams, double>;
using SensorVector = FieldRow<sim::SensorParams, Eigen::Vector3d>;
using ActuatorReal = FieldRow<sim::ActuatorParams, double>;

inline const SensorReal kSensorReals[] = {
    {"accel_noise", "m/s^2", 0, 10, "accelerometer white noise per sample, 1 sigma", &sim::SensorParams::accel_noise},
    {"accel_bias_range", "m/s^2", 0, 5, "initial accelerometer bias, uniform in +-range", &sim::SensorParams::accel_bias_range},
    {"accel_bias_walk", "m/s^2/sqrt(s)", 0, 1, "accelerometer bias random walk", &sim::SensorParams::accel_bias_walk},
    {"accel_scale_range", "", 0, 0.5, "accelerometer scale-factor error per axis, uniform in +-range",
     &sim::SensorParams::accel_scale_range},
    {"accel_vibration", "m/s^2", 0, 50, "accelerometer vibration noise at full throttle, 1 sigma per axis",
     &sim::SensorParams::accel_vibration},
    {"accel_calibration_tilt_range", "rad", 0, 0.2,
     "roll and pitch of the surface during the stored accelerometer calibration, each uniform in +-range",
     &sim::SensorParams::accel_calibration_tilt_range},
    {"accel_resolution", "m/s^2", 0, 1, "accelerometer output resolution, one count (0: continuous)", &sim::SensorParams::accel_resolution},
    {"gyro_noise", "rad/s", 0, 1, "gyro white noise per sample, 1 sigma", &sim::SensorParams::gyro_noise},
    {"gyro_resolution", "rad/s", 0, 0.1, "gyro output resolution, one count (0: continuous)", &sim::SensorParams::gyro_resolution},
    {"imu_temperature_resolution", "K", 0, 10, "IMU temperature resolution, one count (0: continuous)",
     &sim::SensorParams::imu_temperature_resolution},
    {"gyro_bias_range", "rad/s", 0, 1, "initial gyro bias, uniform in +-range", &sim::SensorParams::gyro_bias_range},
    {"gyro_bias_walk", "rad/s/sqrt(s)", 0, 1, "gyro bias random walk", &sim::SensorParams::gyro_bias_walk},
    {"gyro_scale_range", "", 0, 0.5, "gyro scale-factor error per axis, uniform in +-range", &sim::SensorParams::gyro_scale_range},
    {"gyro_vibration", "rad/s", 0, 5, "gyro vibration noise at full throttle, 1 sigma per axis", &sim::SensorParams::gyro_vibration},
    {"imu_cross_axis_range", "", 0, 0.5, "IMU cross-axis sensitivity, each off-diagonal term uniform in +-range",
     &sim::SensorParams::imu_cross_axis_range},
    {"mag_noise", "T", 0, 1e-3, "magnetometer white noise per axis", &sim::SensorParams::mag_noise},
    {"mag_resolution", "T", 0, 1e-5, "magnetometer output resolution, one count (0: continuous)", &sim::SensorParams::mag_resolution},
    {"mag_gm_sigma", "T", 0, 1e-3, "magnetometer Gauss-Markov error, steady sigma", &sim::SensorParams::mag_gm_sigma},
    {"mag_gm_tau", "s", 0, 1e5, "magnetometer Gauss-Markov time constant", &sim::SensorParams::mag_gm_tau},
    {"mag_hard_iron_range", "T", 0, 1e-3, "residual hard iron per axis, uniform in +-range", &sim::SensorParams::mag_hard_iron_range},
    {"mag_soft_iron_range", "", 0, 0.5, "residual soft iron, each term of S - I uniform in +-range",
     &sim::SensorParams::mag_soft_iron_range},
    {"mag_declination", "rad", -3.2, 3.2,
     "magnetic declination at the origin, east positive (unset: the World Magnetic Model's at the origin on `date`; set: overrides it)",
     &sim::SensorParams::mag_declination},
    {"mag_inclination", "rad", -1.6, 1.6,
     "magnetic inclination at the origin, down positive (unset: the World Magnetic Model's at the origin on `date`; set: overrides it)",
     &sim::SensorParams::mag_inclination},
    {"mag_intensity", "T", 1e-6, 1e-3,
     "magnetic field strength at the origin (unset: the World Magnetic Model's at the origin on `date`; set: overrides it)",
     &sim::SensorParams::mag_intensity},
    {"baro_noise", "Pa", 0, 1000, "barometer white noise", &sim::SensorParams::baro_noise},
    {"baro_resolution", "Pa", 0, 100, "barometer pressure resolution, one count (0: continuous)", &sim::SensorParams::baro_resolution},
    {"baro_temperature_resolution", "K", 0, 10, "barometer temperature resolution, one count (0: continuous)",
     &sim::SensorParams::baro_temperature_resolution},
    {"baro_bias_range", "Pa", 0, 5000, "initial barometer bias, uniform in +-range", &sim::SensorParams::baro_bias_range},
    {"baro_bias_walk", "Pa/sqrt(s)", 0, 100, "barometer bias random walk", &sim::SensorParams::baro_bias_walk},
    {"baro_static_error", "", -1, 1, "static-port error, fraction of the dynamic pressure of the relative wind along body x",
     &sim::SensorParams::baro_static_error},
    {"baro_static_error_yp", "", -1, 1, "static-port error, fraction of the dynamic pressure of a relative wind from the right (+y)",
     &sim::SensorParams::baro_static_error_yp},
    {"baro_static_error_yn", "", -1, 1, "static-port error, fraction of the dynamic pressure of a relative wind from the left (-y)",
     &sim::SensorParams::baro_static_error_yn},
    {"baro_static_error_z", "", -1, 1, "static-port error, fraction of the dynamic pressure of the relative wind along body z",
     &sim::SensorParams::baro_static_error_z},
    {"diff_pressure_noise", "Pa", 0, 100, "differential pressure white noise", &sim::SensorParams::diff_noise},
    {"diff_pressure_resolution", "Pa", 0, 100, "differential pressure resolution, one count (0: continuous)",
     &sim::SensorParams::diff_resolution},
    {"diff_pressure_temperature_resolution", "K", 0, 10, "differential pressure sensor's temperature resolution, one count (0: continuous)",
     &sim::SensorParams::diff_temperature_resolution},
    {"diff_pressure_bias_range", "Pa", 0, 100, "initial differential pressure bias, uniform in +-range",
     &sim::SensorParams::diff_bias_range},
    {"diff_pressure_bias_walk", "Pa/sqrt(s)", 0, 10, "differential pressure bias random walk", &sim::SensorParams::diff_bias_walk},
    {"diff_pressure_scale_range", "", 0, 0.5, "pitot installation scale error, uniform in +-range", &sim::SensorParams::diff_scale_range},
    {"gnss_h_sigma", "m", 0, 100, "GNSS horizontal position error per axis, steady-state sigma (Gauss-Markov)",
     &sim::SensorParams::gnss_h_sigma},
    {"gnss_v_sigma", "m", 0, 100, "GNSS vertical position error, steady-state sigma (Gauss-Markov)", &sim::SensorParams::gnss_v_sigma},
    {"gnss_tau", "s", 0, 1e6, "GNSS position error correlation time (book: 1100 s; 0: white)", &sim::SensorParams::gnss_tau},
    {"gnss_vel_noise", "m/s", 0, 10, "GNSS velocity error per axis, steady-state sigma", &sim::SensorParams::gnss_vel_noise},
    {"gnss_vel_tau", "s", 0, 1e4, "GNSS velocity error correlation time (0: white)", &sim::SensorParams::gnss_vel_tau},
    {"gnss_latency", "s", 0, 2, "GNSS fix delivered this long after its time of validity", &sim::SensorParams::gnss_latency},
    {"gnss_elevation_mask", "rad", 0, 1.5, "with gnss_sky: the satellites lie above this elevation (the receiver's mask)",
     &sim::SensorParams::gnss_elevation_mask},
    {"gnss_antenna_cutoff", "rad", -1.5, 1.5, "with gnss_sky: satellites lower above the antenna's plane are lost",
     &sim::SensorParams::gnss_antenna_cutoff},
    {"gnss_reacquisition", "s", 0, 100, "with gnss_sky: a lost satellite back in view is tracked after this time",
     &sim::SensorParams::gnss_reacquisition},
    {"gnss_pdop_mask", "", 0, 100, "with gnss_sky: the receiver outputs no fix with a larger PDOP (0: no mask)",
     &sim::SensorParams::gnss_pdop_mask},
    {"gnss_max_acceleration", "m/s^2", 0, 1000,
     "the receiver's dynamic platform model: its velocity follows accelerations up to this (0: every one)",
     &sim::SensorParams::gnss_max_acceleration},
    {"gnss_lag_tau", "s", 0, 100, "the receiver's velocity change beyond gnss_max_acceleration catches up with this time constant",
     &sim::SensorParams::gnss_lag_tau},
    {"gnss_h_acc", "m", 0, 1000, "reported horizontal accuracy", &sim::SensorParams::gnss_h_acc},
    {"gnss_v_acc", "m", 0, 1000, "reported vertical accuracy", &sim::SensorParams::gnss_v_acc},
    {"gnss_s_acc", "m/s", 0, 100, "reported speed accuracy", &sim::SensorParams::gnss_s_acc},
    {"range_noise_near", "m", 0, 10, "range finder noise below range_far_from, 1 sigma", &sim::SensorParams::range_noise_near},
    {"range_noise_far", "m", 0, 10, "range finder noise at and beyond range_far_from, 1 sigma", &sim::SensorParams::range_noise_far},
    {"range_far_from", "m", 0, 1000, "range finder: distance from which range_noise_far applies", &sim::SensorParams::range_far_from},
    {"range_min", "m", 0, 10, "range finder: nearest distance measured (nearer: -inf)", &sim::SensorParams::range_min},
    {"range_max", "m", 0.1, 1000, "range finder: farthest distance measured (farther: no return, +inf)", &sim::SensorParams::range_max},
    {"origin_lat", "deg", -90, 90, "latitude of the NED origin", &sim::SensorParams::origin_lat},
    {"origin_lon", "deg", -180, 180, "longitude of the NED origin", &sim::SensorParams::origin_lon},
    {"origin_alt", "m", -500, 9000, "altitude (MSL) of the NED origin = the ground (also the magnetic model's height)",
     &sim::SensorParams::origin_alt},
};

inline const SensorVector kSensorVectors[] = {
    {"imu_misalignment", "rad", -0.5, 0.5, "IMU mounting rotation relative to body: roll, pitch, yaw",
     &sim::SensorParams::imu_misalignment},
    {"imu_position", "m", -5, 5, "IMU position from the CG, body FRD", &sim::SensorParams::imu_position},
    {"mag_motor_field", "T", -1e-3, 1e-3, "field of the motor current at full throttle, body FRD", &sim::SensorParams::mag_motor_field},
    {"gnss_antenna_position", "m", -5, 5, "GNSS antenna position from the CG, body FRD", &sim::SensorParams::gnss_antenna_position},
    {"range_position", "m", -5, 5, "range finder position from the CG, body FRD (it looks along body +z)",
     &sim::SensorParams::range_position},
};

inline const ActuatorReal kActuatorReals[] = {
    {"servo_rate_limit", "rad/s", 0, 100, "largest surface rate (0: unlimited)", &sim::ActuatorParams::servo_rate_limit},
    {"servo_deadband", "rad", 0, 0.2, "servo deadband: no motion for a command error below half of it",
     &sim::ActuatorParams::servo_deadband},
    {"motor_tau", "s", 0, 5, "motor spin-up/down time constant (0: at once)", &sim::ActuatorParams::motor_tau},
};

}  // namespace tern::sim_aero
