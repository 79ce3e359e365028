// core/apps/replay/replay_report.hpp: the truth-free replay report (issue 43): what `tern replay`
// prints and writes as replay_report.json when a log has no truth to compare with.
//
// Reads a run directory `tern replay` wrote (docs/sensor-log.md, core/host/record/flight_log.hpp):
// topics/state.csv (the estimate), innovations.csv, gnss.csv, reference.csv (another estimator's
// solution, optional), params.csv (gates, GNSS delay), summary.json (the estimator's own counters
// and resets, the replay's rows played per topic: RowAccount) and sensor_log.yaml (its optional `airborne: [start_s, end_s]`).
//
// The window: sensor_log.yaml's `airborne` if given, else from the first to the last GNSS fix
// (log time t) with a horizontal speed >= 5 m/s, else the whole replay; `Window::rule` says which.
// Comparisons use the window and the samples where the state is valid (valid == 1, origin_valid
// for positions); NIS figures are given over the whole replay and over the window. Each sample of
// the state and the reference is taken at its own time, its `stamp` (a replay records a sample at
// the tick after it), the GNSS fixes at their time of validity.
// Frames and units: errors are estimate minus comparator; angles in deg, wrapped to [-180, 180);
// positions in m in the estimate's NED frame (the comparator's lat/lon/alt converted with
// tern::GeoOrigin at state.csv's origin_lat/lon/alt of the same row); velocities in m/s.
// A figure without samples has NaN values, 0 samples and its `rule` says why.
//
// Each anomaly the report shows is explained in one line where it shows (ReportNote, below): the
// reference's altitude on another datum, a magnetometer rejected, roll/pitch/yaw far from the
// reference's and which of the two the sensors contradict (SpecificForceCheck: no yaw read), a NIS
// far from 1, the magnetometer's field against the model (MagFieldCheck). Every explanation
// comes from the run's data by a threshold stated below (never from the flight's name); the
// extra tables they read are topics/baro.csv (pressure) and topics/mag.csv (field).
//
// Errors: ConfigError with one line "file:line: ..." for a malformed CSV row or a bad
// sensor_log.yaml `airborne`; "run_dir: no topics/state.csv" when there is no estimate.
// Missing optional topics are not errors: their section is absent, saying so.
#pragma once

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tern::core {

/// One error figure: RMS and largest magnitude of (estimate - comparator).
struct ErrorFigure {
  double rms = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();   ///< largest |error| (vector norm for 2-D)
  double mean = std::numeric_limits<double>::quiet_NaN();  ///< mean error, signed (a bias: e.g. another altitude datum); 2-D: mean norm
  std::size_t samples = 0;
  std::string unit;  ///< "deg", "m", "m/s"
  std::string rule;  ///< what was compared where (or why nothing was)
};

/// The part of the replay the comparisons cover.
struct ReplayWindow {
  double start_s = 0.0, end_s = 0.0;  ///< flight time (the log's t), s
  std::string rule;                   ///< which rule produced it
};

/// NIS of one innovations column over a stretch: per innovations message with a fused sample (the
/// message carries the largest test ratio NIS / gate since the previous one; -1: none fused).
struct NisStats {
  std::size_t count = 0;     ///< messages with a fused sample
  std::size_t rejected = 0;  ///< of which test ratio > 1
  double share_rejected = std::numeric_limits<double>::quiet_NaN();
  double mean_nis = std::numeric_limits<double>::quiet_NaN();  ///< NaN when the gate is unknown
  double p50_nis = std::numeric_limits<double>::quiet_NaN();   ///< percentiles: linear between order statistics
  double p95_nis = std::numeric_limits<double>::quiet_NaN();
  double p99_nis = std::numeric_limits<double>::quiet_NaN();
  double p50_ratio = std::numeric_limits<double>::quiet_NaN();  ///< the same of the test ratio (gate-free)
  double p95_ratio = std::numeric_limits<double>::quiet_NaN();
  double p99_ratio = std::numeric_limits<double>::quiet_NaN();
};

struct MeasurementReport {
  std::string name;  ///< innovations.csv column: gnss_pos, gnss_vel, baro, diff_pressure, mag, sideslip, normal_force
  std::string gate;  ///< where the gate came from ("ekf.gnss_pos_gate = 16.266") or why it is unknown
  NisStats whole, window;
};

/// One measurement model's counters of summary.json (<model>_accepted, _rejected, _mean_nis).
struct ModelCounters {
  std::string model;
  double accepted = 0.0, rejected = 0.0;
  double mean_nis = std::numeric_limits<double>::quiet_NaN();
};

struct EstimatorCounters {
  std::string instance;                                ///< "" when summary.json names no estimator
  std::vector<ModelCounters> models;                   ///< in summary.json's order
  std::vector<std::pair<std::string, double>> resets;  ///< every "<x>_resets" and "inflations"
};

/// One sensor table's rows against the estimator's samples (summary.json): `rows` the log's table
/// holds (less the rows the replay dropped: time going backwards), `played` by the replay (the
/// rest lie after the tick of the last IMU row, where the replay ends), `received` by the
/// estimator (each one fused, gated out, used to initialise or calibrate, or `invalid`: NaN, out
/// of range, its stamp going backwards), `missed`: samples its input queue could not hold.
/// lost = played - received: 0 when every played sample reached the filter.
struct TopicRows {
  std::string topic;  ///< imu, gnss, baro, diff_pressure, mag
  double rows = 0.0, played = 0.0, received = 0.0, invalid = 0.0, missed = 0.0;
  double lost() const { return played - received; }
};

/// The row account of the sensor tables: the replay instance's `<topic>_rows`/`_played` against
/// the estimator's `<sensor>_received`/`_invalid`/`<input>_missed` in summary.json.
struct RowAccount {
  std::string absent;             ///< "" when counted, else why not
  std::vector<TopicRows> topics;  ///< those the log has, in the order above
  double lost = 0.0;              ///< summed over topics
  double not_played = 0.0;        ///< rows after the replay's end, summed over topics
};

struct Validity {
  double first_valid_s = std::numeric_limits<double>::quiet_NaN();  ///< NaN: never valid
  double share_valid = std::numeric_limits<double>::quiet_NaN();    ///< of the state samples from the first valid one
  std::size_t samples = 0;                                          ///< state samples from the first valid one
  std::size_t valid_to_invalid = 0;                                 ///< transitions after the first valid state
  std::size_t filter_resets = 0;                                    ///< summary.json's filter_resets
  std::size_t divergences = 0;                                      ///< valid_to_invalid + filter_resets
  std::size_t nan_cells = 0, nan_rows = 0;                          ///< in state.csv: must be 0
};

struct ReferenceComparison {
  std::string absent;  ///< "" when compared, else why not
  ErrorFigure roll, pitch, yaw, course, position_h, position_v, velocity_h, velocity_v;
};

struct GnssComparison {
  std::string absent;
  std::string time_rule;  ///< how each fix's time of validity was taken
  std::size_t fixes = 0, fixes_in_window = 0;
  ErrorFigure position_h, velocity_h, course;
  double share_pos_accepted = std::numeric_limits<double>::quiet_NaN();  ///< estimator counters, whole replay
  double share_vel_accepted = std::numeric_limits<double>::quiet_NaN();
};

struct WindReport {
  std::string absent;
  std::size_t samples = 0;
  double mean_speed = std::numeric_limits<double>::quiet_NaN();  ///< m/s, of |(w_n, w_e)|
  double max_speed = std::numeric_limits<double>::quiet_NaN();
  ErrorFigure vs_reference;  ///< |w - w_ref| horizontal
};

/// The attitude's roll and pitch checked against physics, without any estimator's yaw (issue 61):
/// the specific force the accelerometer measured, f (body axes, its mean over +-kSpecificForceSpan
/// s), against the one the GNSS implies, f_ned = a - g (NED; a from a straight-line fit of the
/// fixes' velocity over the same span, at their time of validity). With R = Rz(psi) L^T and
/// L = Ry(theta) Rx(phi), f = R^T f_ned reads L f = Rz(psi)^T f_ned: in the level frame (x along the
/// heading, z down) the body's specific force L f must have the vertical part f_ned,z, which no
/// yaw changes, and a horizontal part of length h = |f_ned,x f_ned,y| in a direction that only
/// the yaw sets. The check solves the yaw per epoch as a free parameter: the nearest such vector
/// lies along L f's own horizontal part, so the residual, in level axes,
///   res_lev = ((p - h) u, (L f)_z - f_ned,z),  p = |(L f)_xy|, u = (L f)_xy / p,
/// is the smallest any yaw leaves (res = L^T res_lev in body axes; pitch error -res_x / |f_ned|,
/// roll error res_y / |f_ned|, small angles: a tilt delta moves f by |f| delta, g / cos(bank) in a
/// coordinated turn). It uses the attitude's roll and pitch
/// only: an estimator's yaw error, which R^T (a - g) turns into a tilt of about yaw error * h / g,
/// cannot enter. Observability: a tilt error delta (level axes) moves L f by delta x L f; with
/// L f = (h e, f_z) the part of delta about e (the horizontal specific force's direction) moves it
/// across e, which a yaw of delta_e f_z / h undoes, so that tilt is unobservable once h is large
/// against g delta; the part about the horizontal axis across e changes p and the vertical part:
/// observed. Hence the per-axis rule: pitch is judged only where the GNSS acceleration across the
/// track (turns) is at most kFreeYawAxis (replay_specific_force.cpp), roll only where the one
/// along it (speeding up, slowing down) is; the track's axes are the GNSS velocity's, the same
/// for every attitude judged (the heading differs from the track by the crab angle, which mixes
/// sin(crab) of one into the other). In unaccelerated flight
/// (h -> 0) the yaw is unobservable and irrelevant: roll and pitch come from gravity alone, both
/// judged. Limits: the GNSS acceleration's noise n enters h, so in straight flight the free yaw
/// turns up to |n| of it against a tilt error (a residual short by up to |n| / g rad; the
/// accelerometer's bias, misalignment and the GNSS's acceleration error are the same for every
/// attitude checked: an attitude that needs a large constant tilt needs an implausible
/// accelerometer bias instead, 0.1 m/s^2 is 0.6 deg). The estimator fuses the same sensors, so
/// this checks consistency, not truth; it decides between two estimates of one flight (the
/// estimate's and the reference's), judged at the same epochs by the same rule.
struct SpecificForceCheck {
  std::string absent;                           ///< "" when checked, else why not
  std::string rule;                             ///< what was compared where
  std::size_t epochs = 0;                       ///< check epochs (every kSpecificForceStep s of the window with enough fixes)
  std::size_t accelerated = 0;                  ///< of those, where h > kFreeYawAxis: the yaw solvable, one tilt axis not
  ErrorFigure pitch, roll;                      ///< the estimate's implied tilt errors, deg
  ErrorFigure reference_pitch, reference_roll;  ///< the reference's, deg (samples 0 without a reference)
};

/// The magnetometer's field against the World Magnetic Model (issue 61): whether a mismatch is the
/// model's or the log's calibration. Measured in the window (mag.csv, its own axes; valid state):
/// the strength |B|, and, levelled by the estimate's roll and pitch (no yaw), the horizontal and
/// vertical parts and the inclination; its median strength in each 45 deg sector of the
/// estimate's yaw (a hard or soft iron the calibration left makes the strength change with
/// heading; the Earth's field does not). The model: tern/magnetic_model.hpp at the origin on
/// ekf.mag_model_date, with its expected error: the WMM's own error model (kWmmErrorIntensity,
/// kWmmErrorInclination: the crustal field included) plus, for every year outside the model's
/// span, the drift of the WMM's secular-variation forecasts at this place (each shipped model
/// carried to its successor's epoch against the successor there, per year, the largest). The note (replay_note_mag.cpp) says which of the
/// two a mismatch is.
struct MagFieldCheck {
  std::string absent;  ///< "" when checked, else why not
  std::string rule;
  std::size_t samples = 0;
  double intensity = NAN, intensity_p5 = NAN, intensity_p95 = NAN;  ///< |B| median and 5-95 %, uT
  double horizontal = NAN, vertical = NAN, inclination = NAN;       ///< medians: uT, uT (down), deg
  std::string model;                                                ///< "WMM-2015v2 on 2014.11 at the origin"
  double model_intensity = NAN, model_horizontal = NAN, model_vertical = NAN, model_inclination = NAN;
  double years_outside = 0.0;                             ///< years of extrapolation beyond the model's span
  double drift_intensity = NAN, drift_inclination = NAN;  ///< the forecast's drift: uT/yr, deg/yr
  std::string drift_rule;
  double expected_intensity = NAN, expected_inclination = NAN;  ///< the model's expected error here: uT, deg
  std::size_t sectors = 0;                                      ///< heading sectors with >= 10 samples
  double heading_spread = NAN;                                  ///< max - min of their median |B|, uT
};
/// The WMM's uncertainty (its error model, commission and omission i.e. crustal errors, over a
/// 5-year span): NCEI's WMM2025 technical report, Table 3 "Uncertainty estimates provided by the
/// WMM2025 error model": F 138 nT, I 0.20 deg (WMM2020's: 145 nT, 0.21 deg).
constexpr double kWmmErrorIntensity = 0.138;   ///< uT
constexpr double kWmmErrorInclination = 0.20;  ///< deg

/// One anomaly the report shows, explained in one line where it shows (replay_notes*.cpp). Each is
/// derived from the run's data by a stated rule, a threshold on a measured figure (constants
/// below), never from the flight's name: the reference's altitude on another datum, a sensor
/// rejected and what its data show, an attitude gap that the physics check puts on one side, a
/// NIS far from 1 and the setting behind it.
struct ReportNote {
  /// The figures it explains, as replay_report.json names them ("reference.position_vertical",
  /// "measurements.mag", "estimator.models.mag"): the JSON objects get it as their "note"; the
  /// printed table shows it under the row of the first.
  std::vector<std::string> where;
  std::string text;  ///< one line: what was measured, what the data say caused it, whether it is a defect
};

/// Note rules (replay_notes*.cpp).
constexpr double kDatumOffsetNote = 10.0;   ///< m: |median reference - estimate altitude| above this: another datum
constexpr double kDatumMatch = 3.0;         ///< m: |median| below this: the reference's altitude is that candidate datum
constexpr double kAttitudeGapNote = 2.0;    ///< deg RMS of roll or pitch against the reference: the physics check says whose
constexpr double kRefereeMargin = 1.25;     ///< one attitude's specific-force RMS this many times the other's: that one is off
constexpr double kRejectedNote = 0.5;       ///< share of a magnetometer model's samples rejected
constexpr double kFieldOffNote = 0.15;      ///< |measured / the Earth's field - 1| beyond this: not the Earth's field alone
constexpr double kMagSilentNote = 10.0;     ///< s: no magnetometer fused for this long before the window's end is said
constexpr double kYawGapNote = 10.0;        ///< deg RMS of yaw against the reference: the GNSS course says whose
constexpr double kLowNisNote = 0.3;         ///< mean NIS below: the filter allows that sensor more noise than it has
constexpr double kHighNisNote = 3.0;        ///< mean NIS above: less noise than it has, or a sensor that disagrees
constexpr double kMagModelMargin = 3.0;     ///< a field this many expected errors from the model's is not the model's
constexpr double kMagHeadingSpread = 0.03;  ///< strength changing with heading by this share of it: a calibration left
constexpr double kSlowImuNote = 0.02;       ///< s: a median IMU interval longer than this is named in the attitude notes

struct ReplayReport {
  std::filesystem::path run_dir;
  double replay_start_s = 0.0, replay_end_s = 0.0;  ///< state.csv's first and last t
  ReplayWindow window;
  Validity validity;
  std::vector<MeasurementReport> measurements;  ///< empty: innovations.csv absent
  std::string measurements_absent;
  EstimatorCounters counters;
  RowAccount rows;
  ReferenceComparison reference;
  GnssComparison gnss;
  WindReport wind;
  SpecificForceCheck specific_force;
  MagFieldCheck mag_field;
  std::vector<ReportNote> explanations;  ///< the anomalies above, each explained (replay_notes.cpp)
  std::vector<std::string> notes;        ///< partial last lines and the like
};

/// Builds the report of a finished replay's run directory. Throws ConfigError (see above).
ReplayReport make_replay_report(const std::filesystem::path& run_dir);

/// The table `tern replay` prints (plain text, lines of at most ~100 characters, ends with '\n').
std::string format_replay_table(const ReplayReport& report);

/// Everything in the report, each figure with its rule and sample count (replay_report.json); a
/// figure an explanation is about gets it as "note", and "notes" lists every explanation as
/// "where: text" after the partial-line notes.
nlohmann::json to_json(const ReplayReport& report);

/// Writes to_json(report) as run_dir/replay_report.json (2-space indent). Throws ConfigError
/// "path: cannot write" on failure.
void write_replay_report(const ReplayReport& report);

}  // namespace tern::core
