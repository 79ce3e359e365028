// The replay report's magnetometer field against the World Magnetic Model (replay_report.hpp,
// MagFieldCheck): the measured strength, its levelled horizontal and vertical parts and its
// inclination against the model's at the origin on the model date, the model's expected error
// there (its error model plus its forecast's drift for each year of extrapolation), and the
// strength per heading sector (a calibration the log left changes it with heading).
#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "replay/replay_report_parts.hpp"
#include "tern/magnetic_model.hpp"
#include "tern/math.hpp"

namespace tern::core::replay_report {

namespace {

constexpr double kSectorDeg = 45.0;            ///< heading sector width
constexpr std::size_t kMinSectorSamples = 10;  ///< fewer samples in a sector: not compared
constexpr double kSpanYears = 5.0;             ///< each WMM's span (tern/magnetic_model.hpp)

struct Measured {
  std::vector<double> strength, horizontal, vertical, inclination;
  std::map<int, std::vector<double>> by_sector;
};

/// mag.csv's samples in the window where the state is valid, levelled by its roll and pitch.
Measured measure(const RunTables& run, const ReplayWindow& w) {
  Measured m;
  const CsvTable &mag = *run.mag, &s = run.state;
  const auto& t = mag.at("t");
  for (std::size_t k = 0; k < mag.rows; ++k) {
    if (t[k] < w.start_s || t[k] > w.end_s) continue;
    const Eigen::Vector3d b = Eigen::Vector3d(mag.at("field_x")[k], mag.at("field_y")[k], mag.at("field_z")[k]) * 1e6;  // uT
    const auto br = bracket(s.at("t"), t[k], kMaxGap);
    if (!b.allFinite() || !br || !(s.at("valid")[br->k] > 0.5)) continue;
    const double phi = lerp(s.at("phi"), *br, true), theta = lerp(s.at("theta"), *br, true), psi = lerp(s.at("psi"), *br, true);
    if (!std::isfinite(phi + theta + psi)) continue;
    const Eigen::Vector3d lev = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()) * (Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitX()) * b);
    m.strength.push_back(b.norm());
    m.horizontal.push_back(lev.head<2>().norm());
    m.vertical.push_back(lev.z());
    m.inclination.push_back(std::atan2(lev.z(), lev.head<2>().norm()) * kDegPerRad);
    const double heading = std::fmod(std::fmod(psi * kDegPerRad, 360.0) + 360.0, 360.0);
    m.by_sector[static_cast<int>(heading / kSectorDeg)].push_back(b.norm());
  }
  return m;
}

/// The first valid origin of the state, or nullopt.
std::optional<GeoPoint> origin(const CsvTable& s) {
  if (!s.has("origin_valid") || !s.has("origin_lat") || !s.has("origin_lon") || !s.has("origin_alt")) return std::nullopt;
  for (std::size_t k = 0; k < s.rows; ++k)
    if (s.at("origin_valid")[k] > 0.5) return GeoPoint{s.at("origin_lat")[k], s.at("origin_lon")[k], s.at("origin_alt")[k]};
  return std::nullopt;
}

/// The drift of the WMM's secular-variation forecasts at o, per year: each shipped model carried to
/// its successor's epoch against the successor there; the largest (intensity and inclination each).
void forecast_drift(MagFieldCheck& c, const GeoPoint& o) {
  const auto all = world_magnetic_models();
  c.drift_intensity = c.drift_inclination = 0.0;
  for (std::size_t k = 0; k + 1 < all.size(); ++k) {
    const double epoch = all[k + 1].epoch, years = epoch - all[k].epoch;
    const MagneticField carried = world_magnetic_field(o.lat, o.lon, o.alt, epoch, all[k].name);
    const MagneticField fresh = world_magnetic_field(o.lat, o.lon, o.alt, epoch, all[k + 1].name);
    c.drift_intensity = std::max(c.drift_intensity, std::fabs(carried.intensity - fresh.intensity) * 1e6 / years);
    c.drift_inclination = std::max(c.drift_inclination, std::fabs(carried.inclination - fresh.inclination) * kDegPerRad / years);
    c.drift_rule += fmt::format("{}{} carried to {:.1f} against {}", c.drift_rule.empty() ? "" : ", ", all[k].name, epoch, all[k + 1].name);
  }
  c.drift_rule = "the largest per year of " + c.drift_rule + " at the origin";
}

/// The model's field, its span and its expected error at o on `date`.
void model_field(MagFieldCheck& c, const GeoPoint& o, double date) {
  const MagneticField f = world_magnetic_field(o.lat, o.lon, o.alt, date);
  c.model = fmt::format("{} on {:.2f} at the origin", f.model, date);
  c.model_intensity = f.intensity * 1e6;
  c.model_horizontal = f.ned.head<2>().norm() * 1e6;
  c.model_vertical = f.ned.z() * 1e6;
  c.model_inclination = f.inclination * kDegPerRad;
  for (const auto& m : world_magnetic_models())
    if (m.name == f.model) c.years_outside = std::max({0.0, m.epoch - date, date - (m.epoch + kSpanYears)});
  forecast_drift(c, o);
  c.expected_intensity = kWmmErrorIntensity + c.years_outside * c.drift_intensity;
  c.expected_inclination = kWmmErrorInclination + c.years_outside * c.drift_inclination;
}

void heading_spread(MagFieldCheck& c, const Measured& m) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& [sector, v] : m.by_sector) {
    if (v.size() < kMinSectorSamples) continue;
    ++c.sectors;
    lo = std::min(lo, median(v)), hi = std::max(hi, median(v));
  }
  if (c.sectors >= 2) c.heading_spread = hi - lo;
}

}  // namespace

MagFieldCheck check_mag_field(const RunTables& run, const ReplayReport& r) {
  MagFieldCheck c;
  const auto date = estimator_param(run, r, "mag_model_date");
  const auto o = origin(run.state);
  if (!run.mag)
    c.absent = "absent (no topics/mag.csv)";
  else if (!(run.state.has("valid") && run.state.has("phi") && run.state.has("theta") && run.state.has("psi")))
    c.absent = "absent (state.csv has no valid, phi, theta, psi)";
  else if (!date)
    c.absent = "absent (no mag_model_date in params.csv)";
  else if (!o)
    c.absent = "absent (no valid origin in state.csv)";
  if (!c.absent.empty()) return c;
  const Measured m = measure(run, r.window);
  c.samples = m.strength.size();
  if (c.samples == 0) {
    c.absent = "absent (no magnetometer sample in the window with a valid state)";
    return c;
  }
  c.intensity = median(m.strength), c.intensity_p5 = percentile(m.strength, 0.05), c.intensity_p95 = percentile(m.strength, 0.95);
  c.horizontal = median(m.horizontal), c.vertical = median(m.vertical), c.inclination = median(m.inclination);
  try {
    model_field(c, *o, *date);
  } catch (const std::invalid_argument& e) {
    c.absent = std::string("absent (") + e.what() + ")";
    return c;
  }
  heading_spread(c, m);
  c.rule = fmt::format(
      "mag.csv's samples in the window where the state is valid (its own axes, no mount applied): |B|, and levelled by the "
      "estimate's roll and pitch (no yaw) its horizontal and vertical parts and inclination, medians; the strength's median in "
      "each {:.0f} deg sector of the estimate's yaw with >= {} samples, spread = max - min; the model's expected error = the "
      "WMM error model ({} uT, {} deg) + years outside its span * its forecast's drift here",
      kSectorDeg, kMinSectorSamples, kWmmErrorIntensity, kWmmErrorInclination);
  return c;
}

}  // namespace tern::core::replay_report
