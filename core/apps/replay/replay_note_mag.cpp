// The replay report's note on a rejected magnetometer: when more than kRejectedNote of a
// magnetometer model's samples (the estimator's counters) or of the mag column's innovations
// messages were rejected, what the magnetometer measured there: the field's strength (mag.csv)
// in the window's stretches whose innovations message rejected it (the whole replay's if none),
// against the Earth's field the estimator compared it with (the World Magnetic Model at the
// origin on ekf.mag_model_date, tern/magnetic_model.hpp, or the configured mag_field_strength)
// and against the stretches it accepted; then what the estimator fused instead, and from when it
// fused no magnetometer at all (more than kMagSilentNote before the window's end). And the note on
// the field against the model (MagFieldCheck): whether a mismatch is the model's or the log's
// calibration.
#include <cmath>

#include <fmt/format.h>

#include "replay/replay_report_parts.hpp"
#include "tern/magnetic_model.hpp"

namespace tern::core::replay_report {

namespace {

constexpr std::size_t kMinSamples = 10;  ///< fewer fused samples than this say nothing

const ModelCounters* model(const EstimatorCounters& c, const std::string& name) {
  for (const auto& m : c.models)
    if (m.model == name) return &m;
  return nullptr;
}

double share_rejected(const ModelCounters* m) {
  const double n = m ? m->accepted + m->rejected : 0.0;
  return n >= static_cast<double>(kMinSamples) ? m->rejected / n : NAN;
}

/// |field| (uT) of mag.csv's samples, split by the innovations message that covers each (the
/// message at t_k reports the samples fused in (t_{k-1}, t_k]; log time t for both tables):
/// rejected ones within [from, to], accepted ones anywhere.
struct FieldSplit {
  std::vector<double> rejected, accepted;
};

FieldSplit field_split(const RunTables& run, double from, double to) {
  FieldSplit out;
  if (!run.mag || !run.innovations || !run.innovations->has("mag")) return out;
  const auto &tm = run.mag->at("t"), &x = run.mag->at("field_x"), &y = run.mag->at("field_y"), &z = run.mag->at("field_z");
  const auto &ti = run.innovations->at("t"), &ratio = run.innovations->at("mag");
  std::size_t k = 0;
  for (std::size_t i = 0; i < tm.size(); ++i) {
    while (k < ti.size() && ti[k] < tm[i]) ++k;
    if (k == ti.size()) break;
    const double b = std::sqrt(x[i] * x[i] + y[i] * y[i] + z[i] * z[i]) * 1e6;
    if (ratio[k] > 1.0 && ti[k] >= from && ti[k] <= to)
      out.rejected.push_back(b);
    else if (ratio[k] >= 0.0 && ratio[k] <= 1.0)
      out.accepted.push_back(b);
  }
  return out;
}

/// The last innovations message that carries a magnetometer sample (log time t, s; NaN: none).
double last_fused(const RunTables& run) {
  if (!run.innovations || !run.innovations->has("mag")) return NAN;
  const auto &ti = run.innovations->at("t"), &ratio = run.innovations->at("mag");
  for (std::size_t k = ti.size(); k-- > 0;)
    if (ratio[k] >= 0.0) return ti[k];
  return NAN;
}

/// The Earth's field (uT) the estimator compared with, and where it comes from ("WMM-2015v2 on
/// 2014.11 at the origin"); NaN when neither the model's date nor a fixed strength is known.
std::pair<double, std::string> earth_field(const RunTables& run, const ReplayReport& r) {
  const auto fixed = estimator_param(run, r, "mag_field_strength");
  const auto from_model = estimator_param(run, r, "mag_field_from_model");
  if (fixed && from_model && *from_model == 0.0) return {*fixed * 1e6, "mag_field_strength"};
  const auto date = estimator_param(run, r, "mag_model_date");
  const CsvTable& s = run.state;
  const auto& valid = s.at("origin_valid");
  for (std::size_t k = 0; date && k < s.rows; ++k) {
    if (!(valid[k] > 0.5)) continue;
    try {
      const MagneticField f = world_magnetic_field(s.at("origin_lat")[k], s.at("origin_lon")[k], s.at("origin_alt")[k], *date);
      return {f.intensity * 1e6, fmt::format("{} on {:.2f} at the origin{}", f.model, *date, f.extrapolated ? ", extrapolated" : "")};
    } catch (const std::invalid_argument&) {
      break;
    }
  }
  return {NAN, "unknown"};
}

std::string counters_text(const ModelCounters* m) {
  const double n = m->accepted + m->rejected;
  return fmt::format("{} {:.1f} % rejected: the {}'s {:.0f} of {:.0f} samples (mean NIS {:.1f})", m->model, 100.0 * m->rejected / n,
                     m->model == "mag" ? "3-axis magnetometer" : "magnetic heading", m->rejected, n, m->mean_nis);
}

std::string field_text(const RunTables& run, const ReplayReport& r) {
  FieldSplit f = field_split(run, r.window.start_s, r.window.end_s);
  std::string where = "in the window where it was rejected";
  if (f.rejected.empty()) f = field_split(run, -INFINITY, INFINITY), where = "where it was rejected";
  if (f.rejected.empty()) return "";
  const auto [earth, source] = earth_field(run, r);
  const double lo = percentile(f.rejected, 0.05), hi = percentile(f.rejected, 0.95), mid = median(f.rejected);
  std::string text = fmt::format("; {} the field reads {:.0f}-{:.0f} uT (5-95 %, {} samples) against the Earth's {:.1f} uT ({})", where, lo,
                                 hi, f.rejected.size(), earth, source);
  if (!f.accepted.empty()) text += fmt::format(" and {:.0f} uT (median) where it was accepted", median(f.accepted));
  if (!std::isfinite(earth)) return text;
  if (std::fabs(mid / earth - 1.0) > kFieldOffNote)
    return text + fmt::format(
                      ": {:+.0f} % is not the Earth's field alone (the motor's current, iron nearby, a calibration the log did not undo), "
                      "so rejecting it is right",
                      100.0 * (mid / earth - 1.0));
  return text + ": the strength is the Earth's, its direction is not (a misaligned magnetometer, or a wrong yaw: look)";
}

std::string instead_text(const RunTables& run, const ReplayReport& r, const ModelCounters* failed) {
  std::string text;
  const ModelCounters* heading = model(r.counters, "mag_heading");
  if (heading && heading != failed && heading->accepted > 0)
    text += fmt::format("; what was fused is the heading model (mag_heading): {:.0f} samples accepted at mean NIS {:.2f}",
                        heading->accepted, heading->mean_nis);
  const double last = last_fused(run);
  if (r.window.end_s - last > kMagSilentNote)
    text += fmt::format(
        "; no magnetometer sample is fused after t = {:.1f} s of a window to {:.1f} s: the yaw rests on the GNSS velocity "
        "from then on (tern.log says why)",
        last, r.window.end_s);
  return text;
}

}  // namespace

std::optional<ReportNote> mag_field_note(const ReplayReport& r) {
  const MagFieldCheck& c = r.mag_field;
  if (!c.absent.empty()) return std::nullopt;
  const double off_f = std::fabs(c.intensity - c.model_intensity) / c.expected_intensity;
  const double off_i = std::fabs(c.inclination - c.model_inclination) / c.expected_inclination;
  std::string text = fmt::format(
      "the field measured in the window, {:.1f} uT at {:.1f} deg inclination (horizontal {:.1f}, vertical {:+.1f} uT), against the "
      "model's {:.1f} uT at {:.1f} deg ({:.1f}, {:+.1f}; {}",
      c.intensity, c.inclination, c.horizontal, c.vertical, c.model_intensity, c.model_inclination, c.model_horizontal, c.model_vertical,
      c.model);
  if (c.years_outside > 0.0)
    text += fmt::format(", {:.2f} years outside its span: extrapolated, its forecast drifting {:.3f} uT and {:.3f} deg a year here ({})",
                        c.years_outside, c.drift_intensity, c.drift_inclination, c.drift_rule);
  text += fmt::format(") whose expected error is {:.2f} uT and {:.2f} deg", c.expected_intensity, c.expected_inclination);
  const bool turns = c.heading_spread > kMagHeadingSpread * c.intensity;
  if (off_f <= kMagModelMargin && off_i <= kMagModelMargin)
    return ReportNote{{"mag_field"},
                      text + ": the model fits" +
                          (turns ? fmt::format("; the strength changes with heading by {:.1f} uT: a calibration the log "
                                               "did not undo",
                                               c.heading_spread)
                                 : "")};
  text += fmt::format(": {:.0f} times that in strength and {:.0f} in inclination, which the model (and its extrapolation) cannot make",
                      off_f, off_i);
  if (turns)
    return ReportNote{{"mag_field"},
                      text + fmt::format("; the strength changes with heading by {:.1f} uT over {} sectors: a hard- or soft-iron "
                                         "calibration the log did not undo is the cause",
                                         c.heading_spread, c.sectors)};
  if (std::isfinite(c.heading_spread))
    text += fmt::format("; the strength is steady with heading ({:.1f} uT over {} sectors): no horizontal hard iron; ", c.heading_spread,
                        c.sectors);
  else
    text += "; too few headings flown to test the calibration; ";
  return ReportNote{{"mag_field"},
                    text + fmt::format("the mismatch ({:+.1f} uT vertical, {:+.1f} uT horizontal) is a calibration level "
                                       "flight does not turn (an offset along the body's z axis, a scale error, the motor's "
                                       "current) or a magnetic anomaly at the site, not the model",
                                       c.vertical - c.model_vertical, c.horizontal - c.model_horizontal)};
}

std::optional<ReportNote> magnetometer_note(const RunTables& run, const ReplayReport& r) {
  const ModelCounters* failed = nullptr;
  for (const char* name : {"mag", "mag_heading"})
    if (!failed && share_rejected(model(r.counters, name)) > kRejectedNote) failed = model(r.counters, name);
  const MeasurementReport* column = nullptr;
  for (const auto& m : r.measurements)
    if (m.name == "mag") column = &m;
  const bool column_rejected = column && ((column->whole.count >= kMinSamples && column->whole.share_rejected > kRejectedNote) ||
                                          (column->window.count >= kMinSamples && column->window.share_rejected > kRejectedNote));
  if (!failed && !column_rejected) return std::nullopt;
  ReportNote note;
  if (column) note.where.push_back("measurements.mag");
  std::string text;
  if (failed) {
    note.where.push_back("estimator.models." + failed->model);
    text = counters_text(failed);
  } else {
    text = fmt::format("mag {:.1f} % rejected: of the window's {} innovations messages with a magnetometer sample",
                       100.0 * column->window.share_rejected, column->window.count);
  }
  note.text = text + field_text(run, r) + instead_text(run, r, failed);
  return note;
}

}  // namespace tern::core::replay_report
