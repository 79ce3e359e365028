// core/apps/sysid/flight_data.hpp: a flight's measurements on one time base, as system
// identification and model validation read them (Klein and Morelli, *Aircraft System
// Identification*, ch. 10: data compatibility and conditioning before the regression).
//
// What comes from where (the two-step method: the estimator first, then the model):
//   LOG/topics/imu.csv        specific force a (accelerometer) and angular rate (gyro), body FRD
//   LOG/topics/actuators.csv  the surfaces' and throttle's commands (docs/sensor-log.md)
//   LOG/topics/excitation.csv (optional) the excitation's increments within those commands
//   LOG/topics/diff_pressure.csv (optional) the pitot's differential pressure: the dynamic
//                             pressure the airframe met, gusts included (the estimator's Va, from
//                             its steady wind, misses them)
//   LOG/sensor_log.yaml       (optional) its `airborne: [start_s, end_s]`: where the log says it flew
//   EST/topics/state.csv      the estimator's attitude, gyro bias, air data (Va, alpha, beta from
//                             the wind triangle), wind and position: a `tern replay` of LOG at
//                             log level sysid (the state at every message), or LOG itself
// The IMU's axes are turned into the body's (imu_mount) and its specific force moved to the CG
// (imu_position: a_cg = a - w' x r - w x (w x r)), as the estimator is configured to do.
// The time base is the IMU's, interpolated linearly onto a base of at most 5 ms when the IMU is
// logged slower (a 50-Hz IMU: 4 samples an interval), so that a command's timing is not rounded to
// the IMU's interval. At each base sample the command in force is the last actuators row whose
// stamp plus its surface's delay (command_delay_s) is at or before it (a command that changes
// between two samples counts from the next); commands logged more than 30 ms apart are samples
// of a faster controller's output and are joined linearly instead. Then the prior's first-order
// servo lag (servos.tau), solved exactly from each row's own instant (its stamp plus its delay), not
// from the base sample after it: a delay below the base's interval moves the deflection by itself. The estimate is interpolated linearly
// (angles unwrapped), never across a gap longer than 1 s. Every channel is then low-passed by the same zero-phase filter (a second-order
// Butterworth run forward and backward), so that a linear relation between channels holds after filtering as before it; the angular
// acceleration is the central difference of the filtered rate; then the samples are decimated to `rate_hz`.
//
// Units SI, angles rad, body frame FRD, NED. Errors: ConfigError, one line naming the file
// (a missing table, a column it lacks, fewer than two seconds of estimate).
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "replay/replay_csv.hpp"

namespace tern::core::sysid {

struct FlightSeriesOptions {
  double servo_tau = 0.0;  ///< s, first-order lag from command to deflection (0: none)
  /// s, first-order lag from the throttle's command to the thrust (the motor and propeller spinning
  /// up: motor_lag.hpp); unset: servo_tau, as the surfaces'
  std::optional<double> motor_tau;
  /// s, aileron, elevator, rudder: each command acts this long after its stamp (command_delay.hpp;
  /// negative: the log stamps it late). Before the servo lag; the excitation's parts alike.
  std::array<double, 3> command_delay_s = {0.0, 0.0, 0.0};
  double filter_hz = 10.0;                                 ///< Hz, cut-off of the zero-phase low-pass (0: no filter)
  double rate_hz = 50.0;                                   ///< Hz, rate of the series after decimation (0: the IMU's)
  Eigen::Vector3d imu_position = Eigen::Vector3d::Zero();  ///< m, body FRD from the CG (the estimator's)
  Eigen::Vector3d imu_mount = Eigen::Vector3d::Zero();     ///< rad, roll pitch yaw of the IMU axes in the body's
  /// s: the wind the flow angles are reconstructed against is the estimator's low-passed at
  /// 1 / steady_wind_s Hz (0: at filter_hz, the estimator's own)
  double steady_wind_s = 30.0;
};

/// The airborne part a log declares (sensor_log.yaml's `airborne`), in the log's t.
struct DeclaredAirborne {
  double start_s = 0.0, end_s = 0.0;  ///< s
  std::string source;                 ///< the file it came from
};

/// One vector per channel, all of length size(); sample k of each belongs to time t[k].
struct FlightSeries {
  std::vector<double> t;                          ///< s, log time
  std::vector<double> a_x, a_y, a_z;              ///< specific force, body FRD, m/s^2
  std::vector<double> p, q, r;                    ///< body rates, gyro less the estimated bias, rad/s
  std::vector<double> p_dot, q_dot, r_dot;        ///< angular acceleration, rad/s^2
  std::vector<double> delta_a, delta_e, delta_r;  ///< surface deflections (lagged commands), rad
  std::vector<double> delta_t;                    ///< throttle, 0..1
  /// the excitation's increments within those (topics/excitation.csv: the signal generator's),
  /// lagged and filtered alike, in the same order: delta_a, delta_e, delta_r rad,
  /// delta_t throttle fraction. Independent of the gusts, unlike the commands the controller adds
  /// to them: the instruments of a closed-loop flight (identify.hpp). Empty when the log has none.
  std::vector<double> exc_delta_a, exc_delta_e, exc_delta_r, exc_delta_t;
  std::vector<double> Va;                             ///< estimator's airspeed, m/s
  std::vector<double> alpha, beta;                    ///< flow angles of the reconstructed flight path, rad (header)
  std::vector<double> qbar;                           ///< pitot differential pressure, Pa (NaN: no pitot in the log)
  std::vector<double> phi, theta, psi;                ///< estimator's attitude, 3-2-1 Euler, rad (psi unwrapped)
  std::vector<double> p_n, p_e, p_d;                  ///< estimator's position NED from its origin, m
  std::vector<double> u, v, w;                        ///< estimator's ground velocity, body FRD, m/s
  std::vector<double> w_n, w_e, w_d;                  ///< the steady wind, NED, m/s: the estimator's low-passed; w_d 0 (header)
  std::vector<unsigned char> valid;                   ///< 1 where the estimate was valid and interpolated
  std::vector<std::string> notes;                     ///< one line per table whose rows were not all numbers (the row before each held)
  std::optional<DeclaredAirborne> declared_airborne;  ///< LOG/sensor_log.yaml's `airborne`, if any (airborne.hpp)
  std::size_t size() const { return t.size(); }
};

/// The flow angles of the flight-path reconstruction (Klein and Morelli ch. 10: the kinematic
/// equations with a horizontal wind constant over the manoeuvres; the estimator's vertical wind,
/// seen only through the lift's update, is not taken): the air velocity is the estimator's ground
/// velocity (u, v, w, body FRD) less the steady wind (w_n, w_e, w_d) turned into the body axes by
/// phi, theta, psi; alpha = atan2(w_r, u_r), beta = asin(v_r / |v_r|). Not the estimator's own
/// alpha and beta: its wind follows the gusts through the zero-sideslip and pitot updates
/// (wind_walk), which leaves its sideslip uncorrelated with the true one in the manoeuvres' band.
/// The gusts faster than the steady wind are these angles' error, independent of the
/// accelerometers' (identify.hpp takes them as instruments). NaN where an input is.
void flow_angles_from_steady_wind(FlightSeries& s);

/// What a log must hold before anything is replayed: topics/imu.csv and topics/actuators.csv, and
/// with `replayed` (tern's estimator to run over it) topics/gnss.csv, without which the estimator
/// never initialises (a table without rows is found later: no airborne samples, an estimate never
/// valid). Throws ConfigError naming the file ("no such table: the surfaces' commands are required ...").
void check_sensor_log(const std::filesystem::path& log_dir, bool replayed = true);

/// The estimator's installation, as the estimate's run recorded it in params.csv (the setting
/// `<instance>.imu_position` and `.imu_mount` of any instance; zero when absent), into `o`.
/// Throws ConfigError naming params.csv when a value is not a 3-vector.
void read_installation(const std::filesystem::path& estimate_dir, FlightSeriesOptions& o);

/// The columns read of each table besides its time "t" (read_flight_tables refuses a table
/// without them): topics/imu.csv (m/s^2, rad/s, body FRD as logged), actuators.csv and
/// excitation.csv (rad, throttle 0..1), the estimate's state.csv (docs/sensor-log.md, docs/logs.md).
inline constexpr std::array<const char*, 6> kImuColumns = {"accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"};
inline constexpr std::array<const char*, 4> kCommandColumns = {"delta_a", "delta_e", "delta_r", "delta_t"};
inline constexpr std::array<const char*, 19> kStateColumns = {"valid", "phi", "theta", "psi", "b_x", "b_y", "b_z", "Va",  "alpha", "beta",
                                                              "p_n",   "p_e", "p_d",   "u",   "v",   "w",   "w_n", "w_e", "w_d"};

/// The tables a series is built from, each read once: a second series with other options (the
/// commands' delays: command_delay.hpp) needs no second read of a log of hundreds of MB.
struct FlightTables {
  CsvTable imu, actuators, state;                     ///< topics/imu.csv, actuators.csv; the estimate's state.csv
  std::optional<CsvTable> excitation, diff_pressure;  ///< topics/excitation.csv, diff_pressure.csv, if the log has them
  std::optional<DeclaredAirborne> declared_airborne;  ///< sensor_log.yaml's `airborne`
};

/// The log's own tables (all but the estimate's state), read before the log is replayed: imu.csv
/// and actuators.csv under `log_dir`/topics/, excitation.csv and diff_pressure.csv if there, and
/// sensor_log.yaml's airborne window. The checks of log_units.hpp that the IMU's mounting leaves
/// alone (the commands' units, the specific force's and the rates' magnitudes) are made here, so
/// that a log in another unit fails before its replay; ConfigError naming the file.
FlightTables read_log_tables(const std::filesystem::path& log_dir);

/// The estimate's topics/state.csv under `estimate_dir` into `tables`.
void read_estimate_table(FlightTables& tables, const std::filesystem::path& estimate_dir);

/// Conditions the series from the tables (header).
FlightSeries series_from_tables(const FlightTables& tables, const FlightSeriesOptions& options);

/// The throttle at the times `t` (s; the series' samples), each command in force from its stamp through a
/// first-order lag of `tau` s (solved from each row's instant; rows logged slower than 30 ms joined
/// by lines, as series_from_tables does), neither filtered nor decimated: motor_lag.hpp's search.
/// Throws ConfigError when actuators.csv's delta_t is a number in none of its rows.
std::vector<double> throttle_in_force(const FlightTables& tables, const std::vector<double>& t, double tau);

/// The median of v (the upper of the two middle values for an even count); 0 when v is empty.
double median(std::vector<double> v);

/// A second-order Butterworth low-pass at `cutoff_hz` for samples `dt_s` apart, run forward and
/// backward over `x` (zero phase, magnitude squared). The ends start from the first and last
/// values. Used for every channel alike; exposed for tests.
std::vector<double> zero_phase_lowpass(const std::vector<double>& x, double cutoff_hz, double dt_s);

}  // namespace tern::core::sysid
