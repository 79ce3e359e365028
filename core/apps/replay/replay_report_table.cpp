// The replay report as the plain-text table `tern replay` prints; each explanation (ReportNote)
// under the row of the figure it is about, those without a printed row at the end.
#include <cmath>
#include <set>
#include <string>

#include <fmt/format.h>

#include "replay/replay_report.hpp"

namespace tern::core {

namespace {

/// The explanations whose first figure is `where`, one line each; remembers what was shown.
struct Notes {
  const ReplayReport& r;
  std::set<std::string> shown;
  void under(std::string& out, const std::string& where) {
    for (const auto& e : r.explanations)
      if (!e.where.empty() && e.where.front() == where) out += "    note: " + e.text + "\n";
    shown.insert(where);
  }
  void rest(std::string& out) const {
    for (const auto& e : r.explanations)
      if (e.where.empty() || shown.count(e.where.front()) == 0) out += "note: " + e.text + "\n";
  }
};

std::string num(double v, int decimals = 2) { return std::isfinite(v) ? fmt::format("{:.{}f}", v, decimals) : "-"; }
std::string pct(double share) { return std::isfinite(share) ? fmt::format("{:.1f}", 100.0 * share) : "-"; }

void header(std::string& out, const ReplayReport& r) {
  out += fmt::format("replay report: {}\n", r.run_dir.string());
  out += fmt::format("window {:.3f} - {:.3f} s of {:.3f} - {:.3f} s: {}\n", r.window.start_s, r.window.end_s, r.replay_start_s,
                     r.replay_end_s, r.window.rule);
  const Validity& v = r.validity;
  if (std::isnan(v.first_valid_s))
    out += "estimate: NEVER VALID\n";
  else
    out += fmt::format(
        "estimate: valid {} % of the replay from its first valid state at {:.3f} s; divergences {} ({} valid->invalid, {} filter "
        "resets)\n",
        pct(v.share_valid), v.first_valid_s, v.divergences, v.valid_to_invalid, v.filter_resets);
  if (v.nan_cells > 0) out += fmt::format("!!! NaN in state.csv: {} cells in {} rows !!!\n", v.nan_cells, v.nan_rows);
  if (!r.counters.resets.empty()) {
    out += "resets:";
    for (const auto& [k, n] : r.counters.resets) out += fmt::format(" {} {:.0f}", k, n);
    out += "\n";
  }
}

/// Per sensor table: rows, played, received by the estimator (invalid), lost.
void rows(std::string& out, const ReplayReport& r) {
  const RowAccount& a = r.rows;
  if (!a.absent.empty()) {
    out += "rows: " + a.absent + "\n";
    return;
  }
  out += fmt::format("rows: {:.0f} lost (played, not received by the estimator){}\n", a.lost,
                     a.not_played > 0 ? fmt::format("; {:.0f} after the last IMU row's tick, not played", a.not_played) : "");
  out += fmt::format("  {:<14} {:>8} {:>8} {:>9} {:>8} {:>7} {:>6}\n", "topic", "rows", "played", "received", "invalid", "missed", "lost");
  for (const auto& t : a.topics)
    out += fmt::format("  {:<14} {:>8.0f} {:>8.0f} {:>9.0f} {:>8.0f} {:>7.0f} {:>6.0f}\n", t.topic, t.rows, t.played, t.received, t.invalid,
                       t.missed, t.lost());
}

void nis_row(std::string& out, const NisStats& s) {
  out += fmt::format(" {:>6} {:>6} {:>7} {:>7} {:>7} {:>7} |", s.count, pct(s.share_rejected), num(s.mean_nis), num(s.p50_nis),
                     num(s.p95_nis), num(s.p99_nis));
}

void measurements(std::string& out, const ReplayReport& r, Notes& notes) {
  if (r.measurements.empty()) {
    out += fmt::format("\nNIS: {}\n", r.measurements_absent.empty() ? "absent" : r.measurements_absent);
    return;
  }
  out += "\nNIS per innovations message (the largest since the previous message; per-sample means: the counters below)\n";
  out += "                             | whole replay                               | window\n";
  out += fmt::format("{:<14} {:>6} {:>6} {:>7} {:>7} {:>7} {:>7} |{:>7} {:>6} {:>7} {:>7} {:>7} {:>7} |\n", "measurement", "n", "rej%",
                     "mean", "p50", "p95", "p99", "n", "rej%", "mean", "p50", "p95", "p99");
  for (const auto& m : r.measurements) {
    out += fmt::format("{:<14}", m.name);
    nis_row(out, m.whole);
    nis_row(out, m.window);
    out += m.gate.rfind("gate unknown", 0) == 0 || m.gate.find("(off)") != std::string::npos ? " " + m.gate + "\n" : "\n";
    notes.under(out, "measurements." + m.name);
  }
  if (r.counters.instance.empty()) return;
  out += fmt::format("estimator {} counters (whole replay): model accepted/rejected mean NIS\n", r.counters.instance);
  for (const auto& c : r.counters.models) {
    out += fmt::format("  {:<14} {:>8.0f} / {:<6.0f} {:>8}\n", c.model, c.accepted, c.rejected, num(c.mean_nis, 3));
    notes.under(out, "estimator.models." + c.model);
  }
}

/// One figure's row; `where` names it for its explanations ("reference.roll").
void figure(std::string& out, Notes& notes, const char* name, const ErrorFigure& f, const std::string& where) {
  out += fmt::format("  {:<24} {:>9} {:>9} {:>9} {:>7}\n", fmt::format("{} [{}]", name, f.unit), num(f.rms), num(f.max), num(f.mean),
                     f.samples);
  notes.under(out, where);
}

void comparisons(std::string& out, const ReplayReport& r, Notes& n) {
  const auto& c = r.reference;
  out += fmt::format("\nagainst the reference (window)   RMS       max      mean       n\n");
  if (!c.absent.empty()) {
    out += "  " + c.absent + "\n";
  } else {
    figure(out, n, "roll", c.roll, "reference.roll"), figure(out, n, "pitch", c.pitch, "reference.pitch");
    figure(out, n, "yaw", c.yaw, "reference.yaw"), figure(out, n, "course", c.course, "reference.course");
    figure(out, n, "position horiz.", c.position_h, "reference.position_horizontal");
    figure(out, n, "position vert.", c.position_v, "reference.position_vertical");
    figure(out, n, "velocity horiz.", c.velocity_h, "reference.velocity_horizontal");
    figure(out, n, "velocity vert.", c.velocity_v, "reference.velocity_vertical");
  }
  const auto& g = r.gnss;
  out += "against GNSS at time of validity RMS       max      mean       n\n";
  if (!g.absent.empty()) {
    out += "  " + g.absent + "\n";
  } else {
    figure(out, n, "position horiz.", g.position_h, "gnss.position_horizontal");
    figure(out, n, "velocity horiz.", g.velocity_h, "gnss.velocity_horizontal"), figure(out, n, "course", g.course, "gnss.course");
    out += fmt::format("  fixes accepted: position {} %, velocity {} % (estimator counters); {} fixes, {} in the window\n",
                       pct(g.share_pos_accepted), pct(g.share_vel_accepted), g.fixes, g.fixes_in_window);
  }
  const auto& w = r.wind;
  if (!w.absent.empty())
    out += "wind: " + w.absent + "\n";
  else if (w.vs_reference.samples == 0)
    out += fmt::format("wind (window): mean {} m/s, max {} m/s ({} samples); the reference has no wind\n", num(w.mean_speed),
                       num(w.max_speed), w.samples);
  else
    out += fmt::format("wind (window): mean {} m/s, max {} m/s; against the reference RMS {} m/s, max {} m/s ({} samples)\n",
                       num(w.mean_speed), num(w.max_speed), num(w.vs_reference.rms), num(w.vs_reference.max), w.vs_reference.samples);
}

void specific_force(std::string& out, const ReplayReport& r, Notes& n) {
  const auto& c = r.specific_force;
  if (!c.absent.empty()) {
    out += "attitude vs the specific force: " + c.absent + "\n";
    return;
  }
  out += fmt::format(
      "roll and pitch vs the specific force (accelerometer against GNSS acceleration - g, the yaw solved per epoch, no "
      "estimator's; {} epochs, {} accelerated)\n",
      c.epochs, c.accelerated);
  out += "  implied error                RMS       max      mean       n\n";
  figure(out, n, "roll, estimate", c.roll, "specific_force.roll"), figure(out, n, "pitch, estimate", c.pitch, "specific_force.pitch");
  if (c.reference_roll.samples + c.reference_pitch.samples > 0) {
    figure(out, n, "roll, reference", c.reference_roll, "specific_force.reference_roll");
    figure(out, n, "pitch, reference", c.reference_pitch, "specific_force.reference_pitch");
  }
}

void mag_field(std::string& out, const ReplayReport& r, Notes& n) {
  const auto& c = r.mag_field;
  if (!c.absent.empty()) {
    out += "magnetometer field vs the model: " + c.absent + "\n";
    return;
  }
  out += fmt::format(
      "magnetometer field vs the model ({} samples): {} uT at {} deg against {} uT at {} deg ({}), expected error {} uT, {} deg\n",
      c.samples, num(c.intensity, 1), num(c.inclination, 1), num(c.model_intensity, 1), num(c.model_inclination, 1), c.model,
      num(c.expected_intensity), num(c.expected_inclination));
  n.under(out, "mag_field");
}

}  // namespace

std::string format_replay_table(const ReplayReport& r) {
  std::string out;
  Notes notes{r, {}};
  header(out, r);
  rows(out, r);
  measurements(out, r, notes);
  comparisons(out, r, notes);
  specific_force(out, r, notes);
  mag_field(out, r, notes);
  notes.rest(out);
  for (const auto& n : r.notes) out += "note: " + n + "\n";
  return out;
}

}  // namespace tern::core
