// core/apps/replay/replay_report_parts.hpp: the sections of the replay report (replay_report.hpp),
// each computed from the run's tables; internal to core/apps/replay.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "replay/replay_csv.hpp"
#include "replay/replay_report.hpp"
#include "tern/geodesy.hpp"
#include "tern/math.hpp"

namespace tern::core::replay_report {

/// The run directory's tables, read once.
struct RunTables {
  CsvTable state;
  std::optional<CsvTable> innovations, gnss, reference, imu, baro, mag;
  ParamHistory params;
  nlohmann::ordered_json summary;  ///< {} when summary.json is absent
  std::filesystem::path dir;
};

/// Where tq falls in `t` (increasing): t[k] <= tq <= t[k + 1], f = (tq - t[k]) / (t[k + 1] - t[k]).
/// nullopt outside [t.front(), t.back()] or across a gap longer than max_gap_s.
struct Bracket {
  std::size_t k = 0;
  double f = 0.0;
};
std::optional<Bracket> bracket(const std::vector<double>& t, double tq, double max_gap_s);
/// v at a bracket, linearly (v[k] exactly when both ends are equal); NaN when an end is NaN.
/// Angles (rad) along the shorter arc.
double lerp(const std::vector<double>& v, const Bracket& b, bool angle = false);
/// bracket + lerp: NaN where there is no bracket.
double interpolate(const std::vector<double>& t, const std::vector<double>& v, double tq, double max_gap_s, bool angle = false);
constexpr double kMaxGap = 1.0;  ///< s: longest gap between two samples interpolated across

/// One field of a table over its "time": only its rows with a number (NaN: "not given", as a log
/// that merges two sources leaves the other source's fields empty in each row).
struct Series {
  std::vector<double> t, v;
  Series(const CsvTable& r, const char* name) {
    if (!r.has(name)) return;  // docs/sensor-log.md lets any field be missing
    const auto &time = r.at("time"), &value = r.at(name);
    for (std::size_t k = 0; k < value.size(); ++k)
      if (std::isfinite(value[k])) t.push_back(time[k]), v.push_back(value[k]);
  }
};

/// Index range [first, last) of the samples of `t` within [start, end].
std::pair<std::size_t, std::size_t> index_range(const std::vector<double>& t, double start, double end);

/// Sum of squares, largest magnitude and count of errors: an ErrorFigure in the making.
struct ErrorSum {
  double sum = 0.0, sum2 = 0.0, max = 0.0;
  std::size_t n = 0;
  void add(double e);  ///< e: a scalar error or a vector error's norm; NaN is skipped
  ErrorFigure figure(std::string unit, std::string rule) const;
};

double wrap_pi(double a);
/// The p-quantile (0..1) of v, linear between order statistics (numpy's default); NaN when empty.
double percentile(std::vector<double> v, double p);
double median(const std::vector<double>& v);  ///< percentile(v, 0.5)
constexpr double kMinCourseSpeed = 5.0;       ///< m/s: course compared, and the window found, from this speed

/// The NED frame about state.csv's origin at row k (rebuilt only when the origin changes);
/// nullptr when the row's origin is not valid.
class OriginCache {
 public:
  explicit OriginCache(const CsvTable& s)
      : lat_(s.at("origin_lat")), lon_(s.at("origin_lon")), alt_(s.at("origin_alt")), valid_(s.at("origin_valid")) {}
  const GeoOrigin* at(std::size_t k) {
    if (!(valid_[k] > 0.5)) return nullptr;
    const GeoPoint o{lat_[k], lon_[k], alt_[k]};
    if (!frame_ || frame_->origin() != o) frame_ = std::make_unique<GeoOrigin>(o);
    return frame_.get();
  }
  bool same(std::size_t a, std::size_t b) const { return lat_[a] == lat_[b] && lon_[a] == lon_[b] && alt_[a] == alt_[b]; }

 private:
  const std::vector<double>&lat_, &lon_, &alt_, &valid_;
  std::unique_ptr<GeoOrigin> frame_;
};

/// Adds the column "time" (s): each sample's own time, its `stamp` (ns) when the table has one
/// that never decreases (a replay records a sample at the tick after its stamp), else `t`.
void add_sample_time(CsvTable& table);

ReplayWindow find_window(const RunTables& run);
EstimatorCounters estimator_counters(const nlohmann::ordered_json& summary);
RowAccount row_account(const nlohmann::ordered_json& summary, const EstimatorCounters& counters);
Validity validity(const CsvTable& state, const EstimatorCounters& counters);
std::vector<MeasurementReport> measurement_reports(const RunTables& run, const EstimatorCounters& counters, const ReplayWindow& w);
ReferenceComparison compare_reference(const RunTables& run, const ReplayWindow& w);
GnssComparison compare_gnss(const RunTables& run, const EstimatorCounters& counters, const ReplayWindow& w);
WindReport wind_report(const RunTables& run, const ReplayWindow& w);
SpecificForceCheck check_specific_force(const RunTables& run, const EstimatorCounters& counters, const ReplayWindow& w);
MagFieldCheck check_mag_field(const RunTables& run, const ReplayReport& r);  ///< replay_mag_field.cpp
constexpr double kSpecificForceSpan = 0.6;                                   ///< s either side of a check epoch
constexpr double kSpecificForceStep = 0.5;                                   ///< s between check epochs
/// Each fix's time of validity (s): time_of_validity where non-zero (epoch), else stamp -
/// gnss_delay (the estimator's parameter at the window's start; replay_gnss.cpp).
struct FixTimes {
  std::vector<double> tov;
  std::vector<bool> epoch;
  double delay = 0.0;
  std::string param;  ///< "ekf.gnss_delay"
};
FixTimes fix_times(const RunTables& run, const EstimatorCounters& c, const ReplayWindow& w);

/// The explanations of the report's anomalies (ReportNote), each from its own rule:
/// replay_note_altitude.cpp (the reference's altitude datum), replay_note_mag.cpp (a magnetometer
/// model rejected), replay_note_attitude.cpp (roll and pitch gaps against the specific-force
/// check, a yaw gap against the GNSS course), replay_notes.cpp (NIS far from 1, and the list in
/// the order the table prints).
std::vector<ReportNote> explain_anomalies(const RunTables& run, const ReplayReport& r);
std::optional<ReportNote> altitude_datum_note(const RunTables& run, const ReplayReport& r);
std::optional<ReportNote> magnetometer_note(const RunTables& run, const ReplayReport& r);
std::optional<ReportNote> mag_field_note(const ReplayReport& r);
std::vector<ReportNote> attitude_notes(const RunTables& run, const ReplayReport& r);
/// The estimator's parameter `name` (without its instance) at the window's start; nullopt when
/// params.csv has no number for it.
std::optional<double> estimator_param(const RunTables& run, const ReplayReport& r, const std::string& name);

}  // namespace tern::core::replay_report
