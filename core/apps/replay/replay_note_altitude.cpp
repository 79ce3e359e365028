// The replay report's note on the reference's altitude datum: when the reference's altitude sits
// more than kDatumOffsetNote above or below the estimate's (the median over the window, so a
// climb's lag does not count), which altitude in the log the reference's is: the barometer's ISA
// pressure altitude (against 1013.25 hPa, as a baro-height log records it; docs/sensor-log.md) or
// the GNSS altitude; and which the estimate follows. A pressure altitude differs from one above
// mean sea level by the day's sea-level pressure (QNH): the note gives the QNH at which the two
// agree.
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "replay/replay_report_parts.hpp"
#include "tern/atmosphere.hpp"

namespace tern::core::replay_report {

namespace {

/// The estimate's altitude (m, the origin's datum) at state row k: origin_alt - p_d.
double estimate_alt(const CsvTable& s, std::size_t k) {
  return s.at("origin_valid")[k] > 0.5 && s.at("valid")[k] > 0.5 ? s.at("origin_alt")[k] - s.at("p_d")[k] : NAN;
}

/// The estimate's altitude at time t (s, sample time), interpolated between two valid rows.
double estimate_alt_at(const CsvTable& s, double t) {
  const auto b = bracket(s.at("time"), t, kMaxGap);
  if (!b) return NAN;
  const double a0 = estimate_alt(s, b->k);
  return b->f == 0.0 ? a0 : a0 + b->f * (estimate_alt(s, b->k + 1) - a0);
}

/// Medians over the window of the reference's altitude against the estimate's, the GNSS's and
/// the barometer's pressure altitude, and of the estimate against the GNSS (m; NaN: no samples).
struct DatumMedians {
  double ref_vs_estimate = NAN, ref_vs_gnss = NAN, ref_vs_pressure = NAN, estimate_vs_gnss = NAN;
  double qnh_hpa = NAN;  ///< the sea-level pressure at which the pressure altitude is the GNSS altitude
  std::size_t samples = 0;
};

DatumMedians datum_medians(const RunTables& run, const ReplayReport& r) {
  DatumMedians m;
  const Series ref_alt(*run.reference, "alt");
  const CsvTable& s = run.state;
  const auto [first, last] = index_range(s.at("time"), r.window.start_s, r.window.end_s);
  std::vector<double> d;
  for (std::size_t k = first; k < last; ++k) d.push_back(interpolate(ref_alt.t, ref_alt.v, s.at("time")[k], kMaxGap) - estimate_alt(s, k));
  std::erase_if(d, [](double x) { return std::isnan(x); });
  m.samples = d.size();
  m.ref_vs_estimate = median(d);
  std::vector<double> fix_t, fix_alt;
  if (run.gnss) {
    const FixTimes times = fix_times(run, r.counters, r.window);
    std::vector<double> rg, eg;
    for (std::size_t k = 0; k < run.gnss->rows; ++k) {
      const double t = times.tov[k], alt = run.gnss->at("alt")[k];
      if (!(run.gnss->at("fix_type")[k] >= 3.0) || t < r.window.start_s || t > r.window.end_s || !std::isfinite(alt)) continue;
      fix_t.push_back(t), fix_alt.push_back(alt);
      rg.push_back(interpolate(ref_alt.t, ref_alt.v, t, kMaxGap) - alt);
      eg.push_back(estimate_alt_at(s, t) - alt);
    }
    std::erase_if(rg, [](double x) { return std::isnan(x); });
    std::erase_if(eg, [](double x) { return std::isnan(x); });
    m.ref_vs_gnss = median(rg), m.estimate_vs_gnss = median(eg);
  }
  if (run.baro && run.baro->has("pressure")) {
    std::vector<double> rp, qnh;
    const auto &t = run.baro->at("time"), &p = run.baro->at("pressure");
    for (std::size_t k = 0; k < run.baro->rows; ++k) {
      if (t[k] < r.window.start_s || t[k] > r.window.end_s || !(p[k] > 0.0)) continue;
      rp.push_back(interpolate(ref_alt.t, ref_alt.v, t[k], kMaxGap) - isa_pressure_altitude(p[k]));
      qnh.push_back(p[k] / std::pow(1.0 - kIsaPressureLapse * interpolate(fix_t, fix_alt, t[k], kMaxGap), kIsaPressureExponent) / 100.0);
    }
    std::erase_if(rp, [](double x) { return std::isnan(x); });
    std::erase_if(qnh, [](double x) { return std::isnan(x); });
    m.ref_vs_pressure = median(rp), m.qnh_hpa = median(qnh);
  }
  return m;
}

bool matches(double median_m) { return std::fabs(median_m) < kDatumMatch; }

/// A signed difference in m to 0.1 m, "+0.0" for a round-off below 0.05 m of either sign.
std::string metres(double v) { return fmt::format("{:+.1f}", std::round(v * 10.0) / 10.0 + 0.0); }

}  // namespace

std::optional<ReportNote> altitude_datum_note(const RunTables& run, const ReplayReport& r) {
  if (!r.reference.absent.empty() || r.reference.position_v.samples == 0 || !run.reference) return std::nullopt;
  const DatumMedians m = datum_medians(run, r);
  if (!(std::fabs(m.ref_vs_estimate) > kDatumOffsetNote)) return std::nullopt;
  std::string text = fmt::format(
      "the reference's altitude is {:.1f} m {} the estimate's (median of {} samples in the window; beyond {:.0f} m: another datum, "
      "not an estimation error)",
      std::fabs(m.ref_vs_estimate), m.ref_vs_estimate > 0 ? "above" : "below", m.samples, kDatumOffsetNote);
  const std::string estimate = std::isnan(m.estimate_vs_gnss)
                                   ? ""
                                   : fmt::format("; the estimate's altitude is {} m from the GNSS's (median)", metres(m.estimate_vs_gnss));
  if (matches(m.ref_vs_pressure) && !matches(m.ref_vs_gnss)) {
    text += fmt::format(": it is the barometer's ISA pressure altitude against 1013.25 hPa (median difference {} m)",
                        metres(m.ref_vs_pressure));
    if (std::isfinite(m.ref_vs_gnss))
      text += fmt::format(", {:.1f} m {} the GNSS altitude", std::fabs(m.ref_vs_gnss), m.ref_vs_gnss > 0 ? "above" : "below");
    text += estimate;
    if (std::isfinite(m.qnh_hpa))
      text += fmt::format("; the pressure altitude is the GNSS altitude at a sea-level pressure (QNH) of {:.1f} hPa", m.qnh_hpa);
  } else if (matches(m.ref_vs_gnss)) {
    text +=
        fmt::format(": it is the GNSS altitude (median difference {} m){}: look at the estimate's height", metres(m.ref_vs_gnss), estimate);
  } else {
    std::vector<std::string> not_it;
    if (std::isfinite(m.ref_vs_gnss)) not_it.push_back(fmt::format("the GNSS altitude ({} m)", metres(m.ref_vs_gnss)));
    if (std::isfinite(m.ref_vs_pressure))
      not_it.push_back(fmt::format("the barometer's ISA pressure altitude ({} m)", metres(m.ref_vs_pressure)));
    if (!not_it.empty()) text += fmt::format(": it is not {}", fmt::join(not_it, " nor "));
    text += estimate +
            "; e.g. a height above the WGS-84 ellipsoid and one above mean sea level differ by the geoid's undulation (tens of metres)";
  }
  return ReportNote{{"reference.position_vertical"}, text};
}

}  // namespace tern::core::replay_report
