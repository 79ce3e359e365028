// tern/estimator_ekf/estimator.hpp: the full estimator around the EKF core: sensor checks,
// initialisation (GNSS origin, attitude from specific force and magnetometer, barometer
// calibration), measurement routing, time-outs, GNSS reset, and the msg::State output.
//
// Plain C++: it reads the SDK's sensor message structs (tern/msg/sensors.hpp) and writes
// msg::State, but knows nothing of plugins, ports or parameters, so tests, benchmarks and a
// replay tool can drive it directly. Not thread safe; never allocates after construction except
// when an event is queued (rare: origin set, time-outs, resets).
//
// Life of an estimate:
//   1. Before initialisation, IMU samples feed low-pass averages of accel, gyro and mag, and
//      barometer samples feed the ground calibration (the first baro_calibration_count samples).
//   2. GNSS solutions feed the start-up checks (gnss_checks.hpp: fix type, satellites, reported
//      accuracies, drift while still on the ground, held for a time, as PX4 EKF2 does). A fix
//      that fails one is not used. The first fix passing every check sets the origin (lat, lon,
//      alt): NED positions are those of tern::GeoOrigin (tern/geodesy.hpp) at the origin; the
//      barometer's ground calibration waits for it (its datum is the origin's altitude). The
//      estimator starts on it and on the passing fixes after it, but on the ground its state
//      stays invalid (and origin_valid() false) until the checks have held for
//      gnss_req_hold_time; a check failing before that drops the origin, the filter and the
//      calibration, and the next passing fix starts again. So the hold costs no alignment time on
//      the ground (PX4 aligns before its GNSS checks pass too), and what the origin and the datum
//      are taken from is a fix the checks never faulted. A start in the air (a log that begins in
//      flight, an air launch) is valid at once: there the drift checks cannot run, and an
//      aircraft without any estimate for the hold is worse off than PX4's, whose attitude is valid
//      before its GNSS checks pass; a check failing within the hold still drops that start. Events: the failing checks while waiting (when
//      they change, at most every gnss_check_report_interval), origin_dropped, and when they pass.
//   3. Initialisation needs the origin, init_min_imu_samples IMU samples and, if a magnetometer
//      is expected, a magnetometer sample (or mag_init_wait seconds since the origin was set).
//      At rest, roll and pitch come from the averaged specific force, yaw from the
//      tilt-compensated magnetometer. Moving (GNSS speed >= 0.5 m/s), the specific force is not
//      gravity: the attitude is the TRIAD solution of the mean specific force since the previous
//      fix (body) against the GNSS velocity difference minus gravity (NED), with the field as
//      the second vector; a moving aircraft therefore initialises at its second fix. Without a
//      magnetometer, yaw is the GNSS course when moving, else 0 with a 1-rad sigma. The gyro
//      bias comes from the averaged gyro when at rest; in flight the wind comes from the air
//      triangle w = v_gnss - Va_pitot R e1 (alpha = beta = 0), so that the first pitot and
//      sideslip updates do not have to pull yaw and wind apart from a zero wind.
//   4. Then each IMU sample propagates the filter; each other sensor sample is an update. Each
//      pitot sample also brings the aircraft-model updates (measurements.hpp): the side force
//      (body y) and the normal force (body z, the lift) from the accelerometer averaged since
//      the previous one, which measure the air velocity across the airframe.
// NaN/Inf or out-of-range samples are rejected and counted, never used. Each sample is fused at
// its time of validity (stamp - delay; GNSS: the receiver's epoch, time_of_validity) with the
// state history (history.hpp), so a fix 120 ms late corrects the state of its instant.
// Geometry: the GNSS models include the antenna lever arm; IMU samples are rotated by the mount
// and moved to the CG (imu_position). A sensor that was heard from and falls silent longer than
// its time-out raises a sensor_timeout event (sensor_recovered when it comes back); time-outs
// run on the caller's clock (check_timeouts), so a silent IMU is noticed within imu timeout.
// status(): invalid before initialisation, while the IMU is silent, or when the covariance says
// the tilt or position is lost; degraded (with the sensors' bits) when a sensor timed out or the
// GNSS position keeps being rejected. An IMU silent longer than imu_reinit_gap loses the attitude:
// the filter re-initialises in flight (origin and barometer calibration kept).
// Robust gating: after inflate_after consecutive rejections of the GNSS position (barometer) the
// position (barometer-bias) variance is inflated by NIS / gate and the sample fused again; GNSS
// positions still rejected for gnss_reset_time reset position and velocity, at most once per
// reset_min_interval unless the innovation exceeds gnss_fault_distance. After a GNSS time-out
// (dead reckoning on IMU, airspeed and wind) the filter takes the returning GNSS at once, but
// the published position blends the correction in: the jump goes into an output offset that
// decays with time constant gnss_recovery_time (the filter stays optimal, the controllers see
// no step).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tern/estimator_ekf/estimator_config.hpp"
#include "tern/estimator_ekf/filter.hpp"
#include "tern/estimator_ekf/history.hpp"
#include "tern/estimator_ekf/measurements.hpp"
#include "tern/estimator_ekf/yaw_gsf.hpp"
#include "tern/geodesy.hpp"
#include "tern/magnetic_model.hpp"
#include "tern/msg/estimator.hpp"
#include "tern/msg/sensors.hpp"
#include "tern/msg/state.hpp"
#include "tern/math.hpp"

namespace tern::ekf {

/// Counters of one sensor.
struct SensorCounters {
  std::uint64_t received = 0;  ///< messages offered
  std::uint64_t invalid = 0;   ///< NaN/Inf, out of range or stamp going backwards
  std::uint64_t timeouts = 0;  ///< times it fell silent longer than its time-out
  bool timed_out = false;
  Nanos last_stamp = -1;  ///< stamp of the last valid message (-1: none yet)
};

enum class EventKind : std::uint8_t {
  origin_set,
  initialized,
  baro_calibrated,
  sensor_timeout,
  sensor_recovered,
  gnss_reset,
  imu_gap,
  filter_reset,
  first_invalid,
  mag_reset,
  inflated,
  imu_lost,
  too_old,
  gnss_yaw_reset,
  gnss_velocity_reset,
  gsf_yaw_reset,
  gnss_checks_failing,
  gnss_checks_passed,
  origin_dropped,
  mag_resumed,
  launch_yaw_alignment,
  gnss_epoch_ignored
};

/// Something worth a log line. `value`: the gap for imu_gap and imu_lost, the innovation norm
/// for gnss_reset, the variance factor for inflated, the age (s) for too_old, the failing checks
/// (gnss_check bits) for gnss_checks_failing, the wait since the first fix (s) for gnss_checks_passed,
/// the stamp less the receiver's time_of_validity (s) for gnss_epoch_ignored.
struct Event {
  Nanos stamp = 0;
  EventKind kind = EventKind::initialized;
  Sensor sensor = Sensor::imu;
  double value = 0.0;
};
/// One line describing the event, e.g. "gnss: no valid message for 1.2 s (time-out 1 s)".
std::string describe(const Event& e);

class Estimator {
 public:
  explicit Estimator(const EstimatorConfig& config = {});

  /// New figures (keeps the state; noise and gates apply from the next sample).
  void set_config(const EstimatorConfig& config);
  const EstimatorConfig& config() const { return cfg_; }
  /// Whether to wait (up to mag_init_wait) for a magnetometer before initialising.
  void expect_mag(bool expected) { expect_mag_ = expected; }
  /// Whether a sensor is wired (default: every one): an expected sensor that never delivers a
  /// valid sample times out counted from the first check_timeouts() (the start), as one that
  /// stops does from its last sample. Not expected: its time-out starts at its first sample (an
  /// unwired sensor, or any sensor of a replayed log, whose clock may start anywhere).
  void expect(Sensor s, bool expected) { expected_[static_cast<int>(s)] = expected; }
  /// A new flight: the estimator as constructed with the current configuration and sensor
  /// wiring (expect(), expect_mag()): no origin, no calibration, counters and events cleared.
  /// Every member is per-flight state except those three, so the whole object is replaced.
  void reset();

  /// One IMU sample: propagates (after initialisation) to its stamp. Returns false if rejected.
  bool add_imu(const msg::Imu& m);
  bool add_gnss(const msg::Gnss& m);
  bool add_baro(const msg::Baro& m);
  bool add_diff_pressure(const msg::DiffPressure& m);
  bool add_mag(const msg::Mag& m);
  /// The current aileron, elevator and rudder deflections (rad), for the side- and normal-force models.
  void set_controls(double delta_a, double delta_e, double delta_r) {
    side_force_.delta_a = delta_a;
    side_force_.delta_r = delta_r;
    normal_force_.delta_e = delta_e;
  }
  /// Raises time-out events for sensors silent for longer than their time-out at `now`. Call it
  /// on a clock, not on IMU samples: a silent IMU is noticed only this way.
  void check_timeouts(Nanos now);
  /// Health of the estimate (health.cpp): invalid before initialisation, when the IMU timed out
  /// or the covariance says the tilt or position is lost; degraded when an expected sensor timed
  /// out or its measurements keep being rejected (bits: msg::sensor_bit).
  msg::StateStatus status(std::uint8_t* degraded_sensors = nullptr) const;
  /// The largest test ratio (NIS / gate) of each measurement since the last call.
  msg::Innovations take_innovations(Nanos stamp);

  bool initialized() const { return initialized_; }
  /// The origin is set and the GNSS start-up checks have held, or it was set in the air (before
  /// that it is provisional).
  bool origin_valid() const { return origin_.has_value() && (gnss_checks_.passed() || started_in_air_); }
  /// The estimate as a message (valid = status() is ok or degraded). stamp: that of the last
  /// IMU sample.
  msg::State state() const;
  /// The same into an existing message (allocation free).
  void fill_state(msg::State& s) const;
  /// The body's attitude: the filter's, turned back by the board's tilt the level calibration
  /// put into the accelerometer offset (accel_level_calibrated; otherwise the filter's).
  Eigen::Quaterniond body_attitude() const;
  /// Variance of the published attitude error (body frame, rad^2): the filter's, with the tilt
  /// correction's and the level's or the mount's uncertainty.
  Vec3 body_attitude_variance() const;

  const Filter& filter() const { return filter_; }
  const SensorCounters& counters(Sensor s) const { return counters_[static_cast<int>(s)]; }
  const GnssPosition& gnss_position_model() const { return gnss_pos_; }
  const GnssVelocity& gnss_velocity_model() const { return gnss_vel_; }
  /// The counters of the GNSS velocity model in use (3-D, or north-east without use_gnss_vel_d).
  const UpdateStats& gnss_velocity_stats() const { return cfg_.use_gnss_vel_d ? gnss_vel_.stats : gnss_vel_ne_.stats; }
  UpdateStats& gnss_velocity_stats() { return cfg_.use_gnss_vel_d ? gnss_vel_.stats : gnss_vel_ne_.stats; }
  const Magnetometer& mag_model() const { return mag_; }
  const MagHeading& mag_heading_model() const { return mag_heading_; }
  const BaroAltitude& baro_model() const { return baro_; }
  /// Variance of the barometer's calibration datum (the altitude it was calibrated against), m^2.
  double baro_datum_variance() const { return baro_datum_var_; }
  const PitotAirspeed& diff_pressure_model() const { return pitot_; }
  const ZeroSideslip& sideslip_model() const { return sideslip_; }
  const SideForce& side_force_model() const { return side_force_; }
  const NormalForce& normal_force_model() const { return normal_force_; }
  std::uint64_t gnss_resets() const { return gnss_resets_; }
  std::uint64_t inflations() const { return inflations_; }
  /// Fixes whose satellites changed, each taken as a jump of the GNSS error (gnss_constellation_jumps).
  std::uint64_t constellation_jumps() const { return constellation_jumps_; }
  /// The largest variance factor an inflation of the states `s` measures has applied (0: never inflated).
  double inflation_max(Sensor s) const { return inflation_max_[static_cast<std::size_t>(s)]; }
  std::uint64_t mag_resets() const { return mag_resets_; }
  /// The Earth's field the magnetometer is compared with: the model's at the origin once it is
  /// set (mag_field_from_model), else the configured one.
  const tern::MagneticField& earth_field() const { return field_; }
  /// Yaw resets to the GNSS course in flight (the magnetometer then tested, not fused, until it agrees).
  std::uint64_t gnss_yaw_resets() const { return gnss_yaw_resets_; }
  std::uint64_t filter_resets() const { return filter_resets_; }
  /// The GNSS start-up checks (their verdict, the failing checks and drifts while waiting).
  const GnssChecks& gnss_checks() const { return gnss_checks_; }
  /// The magnetometer is tested, not fused, since a yaw reset to GNSS (mag_resume_time).
  bool mag_inhibited() const { return mag_inhibited_; }
  /// Times its fusion resumed after such a reset (its heading consistent again).
  std::uint64_t mag_resumes() const { return mag_resumes_; }

  /// Events since the last call (the caller logs them).
  std::vector<Event> take_events();
  bool has_events() const { return !events_.empty(); }

  /// NED position (m) of a geodetic point relative to the origin (origin must be set).
  Vec3 ned_from_geodetic(double lat_deg, double lon_deg, double alt_m) const;
  /// Rotation body -> NED from a specific force (body, at rest: -R^T g e3) and a magnetic field
  /// (body) given the field's declination (rad); yaw from the tilt-compensated field.
  static Eigen::Quaterniond attitude_from_accel_mag(const Vec3& f_body, const Vec3& m_body, double declination);
  /// The same without a magnetometer: roll and pitch from the specific force, yaw given.
  static Eigen::Quaterniond attitude_from_accel(const Vec3& f_body, double psi);
  /// Rotation body -> NED from two vector pairs, TRIAD (Black 1964; Markley & Crassidis,
  /// "Fundamentals of Spacecraft Attitude Determination and Control", sec. 5.2.1): the primary
  /// pair (here the specific force: f_ned = a_ned - g e3, a_ned from GNSS velocity) is matched
  /// exactly, the secondary (the magnetic field direction) fixes the rotation about it. In level
  /// unaccelerated flight this is attitude_from_accel_mag(); in a turn, a push-over or a
  /// deceleration it is not misled by the non-gravitational acceleration.
  /// Throws std::invalid_argument if a vector is zero or the two pairs are parallel.
  static Eigen::Quaterniond attitude_triad(const Vec3& f_body, const Vec3& f_ned, const Vec3& m_body, const Vec3& m_ned);

 private:
  bool accept(Sensor s, Nanos stamp, bool ok);
  void push(Nanos stamp, EventKind kind, Sensor s, double value = 0.0);
  void try_initialize(const msg::Gnss& m, const Vec3& p_ned, Nanos t_valid);
  void apply_models_config();
  void lose_attitude(Nanos stamp, double gap);
  Vec3 imu_to_cg(const Vec3& accel_body, const Vec3& gyro_body, double dt);
  /// Time of validity of a sample of sensor s stamped `stamp` (stamp - delay).
  Nanos valid_at(Sensor s, Nanos stamp) const;
  /// Filter::update at the time of validity t_v: with the history's state when t_v is before the
  /// last IMU sample (invalid, counted, when older than the whole history).
  template <class Model>
  UpdateResult fuse(Model& model, const typename Model::Vec& z, Nanos t_v);
  /// fuse() without the dead-reckoning smoothing of the published position.
  template <class Model>
  UpdateResult fuse_now_or_then(Model& model, const typename Model::Vec& z, Nanos t_v);
  /// fuse() that, after inflate_after consecutive rejections, inflates the variances of the
  /// states [first, first + n) by the NIS over the gate (Filter::inflate) and fuses again.
  template <class Model>
  UpdateResult fuse_robust(Sensor s, Model& model, const typename Model::Vec& z, Nanos t_v, int first, int n);
  bool gnss_reset_allowed(Nanos stamp, double innovation) const;
  /// The fix's epoch: its time_of_validity when that is at most kMaxGnssEpochAge before its stamp
  /// (not after it), else the stamp (valid_at then takes gnss_delay off); the first refusal is an event.
  Nanos gnss_epoch(const msg::Gnss& m);
  /// Until the start-up checks have held: one fix through them, with their events. True when the
  /// fix may be used (every check passing); a failing one drops an unsettled start.
  bool check_gnss_start(const msg::Gnss& m, bool usable);
  /// The origin, the filter and the barometer calibration a provisional origin started, dropped.
  void drop_unsettled_start(Nanos stamp);
  /// The aircraft's motion for the start-up checks' drift tests (before initialisation).
  GnssChecks::Motion gnss_check_motion(const msg::Gnss& m) const;
  /// The GNSS velocity's north and east (m/s, NED) through GnssVelocityNE (use_gnss_vel_d false).
  UpdateResult fuse_gnss_velocity_ne(const Vec3& vel, Nanos t_v);
  void use_reported_accuracy(const msg::Gnss& m);
  Vec3 gnss_error_variance() const;
  void add_constellation_jump(const msg::Gnss& m);
  void reset_to_gnss(Nanos stamp, const Vec3& p, const Vec3& vel, Nanos t_v);
  /// Sets the sensor states of a re-initialisation (x, P0) to the filter's before it: gyro and
  /// accelerometer biases, S_g, b_m, k_sp with their covariance among themselves.
  void keep_calibration(NominalState& x, Cov& P0) const;
  /// The dynamic pressure q_bar the static port sees (BaroAltitude), Pa: the pitot's last sample,
  /// or 0.5 rho u_r^2 from the estimate while the pitot is silent.
  double dynamic_pressure() const;
  /// In the air: the pitot measured at least min_airspeed within the last 0.5 s.
  bool airborne(Nanos stamp) const;

  EstimatorConfig cfg_;
  Filter filter_;
  GnssPosition gnss_pos_;
  GnssVelocity gnss_vel_;
  GnssVelocityNE gnss_vel_ne_;  ///< gnss_vel_'s north and east rows, without use_gnss_vel_d
  Magnetometer mag_;
  MagHeading mag_heading_;
  BaroAltitude baro_;
  PitotAirspeed pitot_;
  ZeroSideslip sideslip_;
  SideForce side_force_;
  NormalForce normal_force_;
  Vec3 accel_sum_ = Vec3::Zero();  // body specific force summed since the previous pitot sample
  int accel_n_ = 0;                // (the side- and normal-force updates' measurement)
  /// body_attitude()'s Exp(-mu) for the b_a and gravity it was formed with: b_a moves only in
  /// updates, the attitude is published with every IMU sample.
  struct LevelTilt {
    Vec3 b_a = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
    double gravity = 0.0;
    Eigen::Quaterniond exp_minus_mu = Eigen::Quaterniond::Identity();
  };
  mutable LevelTilt level_tilt_;

  bool initialized_ = false;
  bool keep_calibration_ = false;  ///< the next initialisation keeps the sensor states (after an IMU loss)
  bool expect_mag_ = true;
  std::array<bool, kSensorCount> expected_{true, true, true, true, true};
  Nanos first_check_ = -1;  ///< the first check_timeouts() call: when the silence of a never-heard sensor starts
  std::optional<tern::GeoOrigin> origin_;
  GnssChecks gnss_checks_;
  bool started_in_air_ = false;                   ///< the origin was set in the air, before the checks had held
  std::uint32_t reported_failing_ = 0xFFFFFFFFu;  ///< the failing checks last reported (none yet: all ones)
  Nanos checks_reported_ = -1;                    ///< when
  double origin_lat_ = 0.0, origin_lon_ = 0.0, origin_alt_ = 0.0;
  Nanos origin_stamp_ = 0;

  // pre-initialisation averages
  Vec3 accel_avg_ = Vec3::Zero(), gyro_avg_ = Vec3::Zero(), mag_avg_ = Vec3::Zero();
  // before initialisation: the specific force of the last kPreInitImuSpan, by IMU stamp, and the
  // previous fix's velocity and time of validity. The mean specific force between two fixes' times
  // of validity against their velocity difference gives an in-flight initialisation's attitude
  // (by time of validity: a fix arrives its latency late, after IMU samples of later motion).
  struct ImuRecord {
    Nanos stamp;
    Vec3 accel;  ///< specific force at the CG, body axes
    Vec3 gyro;   ///< angular rate, body axes
  };
  std::deque<ImuRecord> pre_init_imu_;
  /// ns: pre_init_imu_'s span: two fixes of a 1-Hz receiver (kMaxInitFixGap apart at most) and its
  /// latency before them
  static constexpr Nanos kPreInitImuSpan = 2 * kNanosPerSecond;
  /// s: the longest interval between two fixes whose velocity difference initialises the attitude
  /// in flight: a 1-Hz receiver's (the slowest common rate; u-blox's default) with its jitter
  static constexpr double kMaxInitFixGap = 1.5;
  int prev_num_sats_ = -1;  // the last fused fix's satellites and HDOP (add_constellation_jump)
  double prev_hdop_ = 0.0;
  Vec3 prev_acc2_ = Vec3::Zero();  // its accuracies squared (h, h, v), m^2
  std::uint64_t constellation_jumps_ = 0;
  Vec3 prev_fix_vel_ = Vec3::Zero();
  Nanos prev_fix_tv_ = -1;
  /// Held still over the last second of pre_init_imu_: the mean angular rate and the rate's RMS
  /// deviation from it both below rest_rate_max (a hand-held aircraft before a launch is not).
  bool still() const;
  /// Mean specific force of pre_init_imu_ over (t0, t1]; nullopt when no sample lies there.
  std::optional<Vec3> mean_specific_force(Nanos t0, Nanos t1) const;
  std::int64_t imu_samples_ = 0, mag_samples_ = 0;
  // barometer calibration: altitude offset = mean(tern::isa_pressure_altitude(p) - altitude estimate)
  int baro_cal_count_ = 0;
  double baro_cal_sum_ = 0.0;
  double baro_cal_q_sum_ = 0.0;  // dynamic pressure over the calibration, Pa (BaroAltitude::q_datum)
  double baro_offset_ = 0.0;
  bool baro_calibrated_ = false;
  /// Variance of the altitude the barometer was calibrated against (the origin's: a GNSS fix's),
  /// m^2. The filter's altitude is the height above that datum; in the frame it adds this.
  double baro_datum_var_ = 0.0;

  double last_diff_pressure_ = 0.0;  // last valid differential pressure, Pa
  Nanos last_diff_stamp_ = -1;
  Nanos imu_stamp_ = -1;
  Vec3 rate_ = Vec3::Zero();       // last bias-removed gyro, body
  Vec3 gyro_body_ = Vec3::Zero();  // last measured gyro in body axes (bias not removed)
  Vec3 omega_dot_ = Vec3::Zero();  // low-passed angular acceleration, body, rad/s^2
  Mat3 R_bi_ = Mat3::Identity();   // IMU axes -> body axes (cfg_.imu_mount)
  StateHistory history_;
  ProcessNoise process_;  // cfg_.process with the GNSS error walks from the reported accuracy
  std::uint64_t inflations_ = 0;
  std::array<double, kSensorCount> inflation_max_{};
  Nanos last_gnss_reset_ = -1;
  Nanos gnss_reject_since_ = -1;
  bool epoch_ignored_ = false;         // a fix's time_of_validity refused (said once)
  Vec3 output_offset_ = Vec3::Zero();  // published position = filter position + this (decays)
  std::uint64_t gnss_resets_ = 0, filter_resets_ = 0, mag_resets_ = 0;
  Nanos mag_reject_since_ = -1;
  Nanos mag_slot_ = -1;  ///< the next magnetometer fusion slot (mag_fusion_interval), -1: the next sample takes one
  Nanos init_stamp_ = -1;
  double last_Va_ = 0.0;  // airspeed of the last applicable pitot sample, m/s (0: none)
  Nanos last_Va_stamp_ = -1;
  /// Yaw to psi (roll and pitch kept) with yaw sigma `sigma`, the wind re-derived from the air
  /// triangle when airborne (wider by the yaw's sigma unless the yaw came from the magnetometer);
  /// `why` (mag_reset, gnss_yaw_reset or gsf_yaw_reset) is the event and the counter.
  void reset_yaw(Nanos stamp, double psi, double sigma, EventKind why);
  /// Yaw from the GNSS (gnss_yaw(): the converged GSF's, else the course), velocity and position
  /// to the fix, the magnetometer tested, not fused (mag_inhibited_, test_stopped_mag); `why` as for reset_yaw.
  void reset_yaw_to_gnss(Nanos stamp, const Vec3& p, const msg::Gnss& m, Nanos t_v, EventKind why);
  /// The same to the yaw `psi` (rad) of 1-sigma `sigma`.
  void reset_yaw_to_gnss(Nanos stamp, const Vec3& p, const msg::Gnss& m, Nanos t_v, EventKind why, double psi, double sigma);
  /// The field at the origin (mag_field_from_model) or the configured one; sets the models.
  void set_earth_field(const tern::MagneticField& f);
  tern::MagneticField field_;
  Nanos gnss_vel_reject_since_ = -1;
  YawGsf gsf_;                     ///< the yaw from IMU and GNSS velocity alone (yaw_gsf.hpp)
  Nanos gsf_disagree_since_ = -1;  ///< the filter's yaw and the GSF's disagree since
  /// The GSF's yaw and sigma when it has converged, else the GNSS course and gnss_yaw_sigma.
  std::pair<double, double> gnss_yaw(const msg::Gnss& m) const;
  bool gsf_converged() const;
  /// The first yaw alignment in flight (launch_course_error): until a fix in motion (fix and filter
  /// at >= 5 m/s, not airborne()'s pitot) confirms the yaw, a rejected velocity whose course is off
  /// the filter's by more than launch_course_error turns the yaw by that difference, resets
  /// velocity and position to the fix and stops the magnetometer as reset_yaw_to_gnss does. True
  /// after the alignment's reset.
  bool align_yaw_in_flight(UpdateResult rv, const msg::Gnss& m, const Vec3& p, Nanos t_v);
  bool inflight_yaw_aligned_ = false;  ///< a fix in motion confirmed the yaw, or a yaw reset to the GNSS set it
  /// After the fix's velocity update `rv`: in the air, velocities rejected for gnss_yaw_reset_time
  /// reset velocity and position to the fix, and the yaw too if it is off. True after a reset.
  bool recover_velocity(UpdateResult rv, const msg::Gnss& m, const Vec3& p, Nanos t_v);
  /// Feeds the fix's velocity to the GSF in the air (stops it on the ground); resets the yaw to it
  /// when the filter's yaw keeps disagreeing with the converged GSF. Returns true after a reset.
  bool check_yaw_with_gsf(const msg::Gnss& m, const Vec3& p, Nanos t_v);
  double accel_nav_ = 0.0;                                  ///< low-passed |NED acceleration|, m/s^2 (GNSS noise in manoeuvres)
  double gnss_vel_sigma_h_ = 0.0, gnss_vel_sigma_v_ = 0.0;  ///< before the manoeuvre term
  bool reported_h_acc_ = false, reported_s_acc_ = false;    ///< the last fix reported h_acc / s_acc
  /// The GNSS noise of the next fix: the receiver's (or the configured) plus the manoeuvre term.
  void set_gnss_noise();
  std::uint64_t gnss_yaw_resets_ = 0;
  bool mag_inhibited_ = false;  ///< after a yaw reset to GNSS: tested (test_stopped_mag), not fused
  Nanos mag_inhibited_since_ = -1;
  Nanos mag_consistent_since_ = -1;  ///< the stopped magnetometer's heading consistent since (-1: not)
  std::uint64_t mag_resumes_ = 0;
  /// While mag_inhibited_: the heading of the field z (Earth-field units) against the filter's
  /// yaw; resumes the fusion after mag_resume_time of consistency (estimator_mag_resume.cpp).
  void test_stopped_mag(Nanos stamp, const Vec3& z);
  /// What the fixes' course did since the GNSS velocity was first rejected (recover_velocity):
  /// its largest rate, and whether it could not be the heading at some fix (slow, steep).
  struct CourseWatch {
    double prev = 0.0;
    Nanos prev_stamp = -1;
    double rate_max = 0.0;  ///< rad/s
    bool not_heading = false;
  };
  CourseWatch course_;
  /// Feeds one fix to course_ (restarted when the velocity is accepted).
  void watch_course(const msg::Gnss& m, bool restart);
  /// Whether a yaw `yaw_error` (rad) from the course of sigma `sigma` is the likely cause of the
  /// rejected velocity rather than the course's lag in a manoeuvre (gnss_course_lag).
  bool yaw_blamed_on_course(double yaw_error, double sigma) const;
  std::array<SensorCounters, kSensorCount> counters_{};
  std::vector<Event> events_;
};

}  // namespace tern::ekf
