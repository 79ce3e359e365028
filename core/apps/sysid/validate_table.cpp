// core/apps/sysid/validate_table.cpp: the side-by-side table `tern validate` prints
// (validate_report.hpp).
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "sysid/validate_report.hpp"
#include "tern/math.hpp"

namespace tern::core::sysid {

double display_scale(const ChannelSpec& c) { return std::string(c.unit).rfind("rad", 0) == 0 ? kDegPerRad : 1.0; }

std::string display_unit(const ChannelSpec& c) {
  const std::string unit = c.unit;
  return unit.rfind("rad", 0) == 0 ? "deg" + unit.substr(3) : unit;
}

std::size_t scored_samples(const std::vector<Window>& windows) {
  std::size_t n = 0;
  for (const Window& w : windows) n += w.end - w.begin - 1;
  return n;
}

double scored_seconds(const ValidationRun& run) {
  double s = 0.0;
  for (const Window& w : run.windows) s += run.t[w.end - 1] - run.t[w.begin];
  return s;
}

namespace {

std::string cell(double v, int decimals) { return std::isfinite(v) ? fmt::format("{:.{}f}", v, decimals) : std::string("-"); }

std::string header(const ValidationRun& run) {
  std::string out = fmt::format("tern validate: {}\n  estimate: {}\n", run.log, run.estimate);
  out += fmt::format("  windows: {} of {:g} s re-initialised from the log ({:.1f} s, {} scored samples)\n  airborne: {}, Va > {:g} m/s\n",
                     run.windows.size(), run.options.window_s, scored_seconds(run), scored_samples(run.windows), run.airborne,
                     run.options.min_Va);
  for (std::size_t i = 0; i < run.files.size(); ++i) {
    const AircraftScore& f = run.files[i];
    out += fmt::format("  [{}] {} ({}, servo lag {:g} s){}\n", i + 1, f.file, f.name, f.servo_tau,
                       f.prediction.diverged ? fmt::format(": {} window(s) diverged", f.prediction.diverged) : "");
  }
  return out;
}

std::string channel_rows(const ValidationRun& run) {
  std::string out = fmt::format("\n{:<8}{:<8}", "channel", "unit");
  for (std::size_t i = 0; i < run.files.size(); ++i)
    out += fmt::format("{:>12}{:>9}{:>9}", fmt::format("[{}] NRMSE", i + 1), "Theil U", "RMS err");
  out += "\n";
  for (std::size_t c = 0; c < kChannels; ++c) {
    const ChannelSpec& spec = kChannelSpecs[c];
    out += fmt::format("{:<8}{:<8}", spec.name, display_unit(spec));
    for (const AircraftScore& f : run.files)
      out += fmt::format("{:>12}{:>9}{:>9}", cell(f.fit[c].nrmse, 3), cell(f.fit[c].theil_u, 3),
                         cell(f.fit[c].rms_error * display_scale(spec), 2));
    out += "\n";
  }
  return out;
}

/// The overall row under the channels (validate.hpp, "Overall") and the line ranking the files.
std::string overall_rows(const ValidationRun& run) {
  const OverallScores o = overall_scores(run.files);
  std::string out = fmt::format("{:<8}{:<8}", "overall", "");
  for (const double v : o.nrmse) out += fmt::format("{:>12}{:>9}{:>9}", cell(v, 3), "", "");
  out.erase(out.find_last_not_of(' ') + 1);
  out += fmt::format("\nranked by the overall NRMSE (geometric mean over {}), best first:", fmt::join(o.channels, " "));
  for (std::size_t i = 0; i < o.ranking.size(); ++i) out += fmt::format("{}[{}]", i ? " < " : " ", o.ranking[i] + 1);
  return out + "\n";
}

std::string residual_rows(const ValidationRun& run) {
  std::string out = fmt::format("\none-step residual RMS (measured - model at the logged state)\n{:<8}{:<8}{:<6}", "axis", "unit", "coef");
  for (std::size_t i = 0; i < run.files.size(); ++i) out += fmt::format("{:>12}{:>10}", fmt::format("[{}] RMS", i + 1), "as coef");
  out += "\n";
  for (std::size_t a = 0; a < kAxes; ++a) {
    out += fmt::format("{:<8}{:<8}{:<6}", kAxisSpecs[a].name, kAxisSpecs[a].unit, kAxisSpecs[a].coefficient);
    for (const AircraftScore& f : run.files)
      out += fmt::format("{:>12}{:>10}", cell(f.one_step[a].rms, 3), cell(f.one_step[a].coefficient_rms, 4));
    out += "\n";
  }
  return out;
}

}  // namespace

std::string format_validate_table(const ValidationRun& run) {
  return header(run) + channel_rows(run) + overall_rows(run) + residual_rows(run) +
         "\nNRMSE: RMS error / std of the measured channel over the scored samples; Theil's U: RMS error / (RMS measured +\n"
         "RMS predicted); 0 is a perfect fit (Klein and Morelli ch. 11; docs/validate.md)\n";
}

}  // namespace tern::core::sysid
