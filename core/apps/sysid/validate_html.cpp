// core/apps/sysid/validate_html.cpp: DIR/index.html of `tern validate`: the table, then per
// channel the measured series (black) against each aircraft file's prediction over the scored
// windows, and a close-up of the first windows, as inline SVG (no script, no external file;
// validate_report.hpp).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "sysid/validate_report.hpp"
#include "tern/math.hpp"

namespace tern::core::sysid {

namespace {

constexpr double kWidth = 960, kHeight = 200, kLeft = 60, kRight = 10, kTop = 10, kBottom = 25;  // px
constexpr std::size_t kMaxPoints = 2000;  ///< per series and plot: longer series are drawn every n-th sample
constexpr std::size_t kCloseUp = 4;       ///< windows in each channel's close-up
const char* const kColours[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};

std::string escaped(const std::string& s) {
  std::string out;
  for (char ch : s) out += ch == '&' ? "&amp;" : ch == '<' ? "&lt;" : ch == '>' ? "&gt;" : ch == '"' ? "&quot;" : std::string(1, ch);
  return out;
}

/// The plot's frame: time and value ranges mapped to pixels.
struct Frame {
  double t0, t1, lo, hi;
  double x(double t) const { return kLeft + (t - t0) / (t1 - t0) * (kWidth - kLeft - kRight); }
  double y(double v) const { return kTop + (hi - std::clamp(v, lo, hi)) / (hi - lo) * (kHeight - kTop - kBottom); }
};

/// The measured channel's range over `windows`, widened by a quarter of its span each way
/// (predictions beyond it are drawn at its edge).
Frame frame_of(const ValidationRun& run, const std::vector<Window>& windows, const std::vector<double>& y, double scale) {
  double lo = INFINITY, hi = -INFINITY;
  for (const Window& w : windows)
    for (std::size_t k = w.begin; k < w.end; ++k) lo = std::min(lo, y[k] * scale), hi = std::max(hi, y[k] * scale);
  const double pad = hi > lo ? 0.25 * (hi - lo) : 1.0;
  return {run.t[windows.front().begin], run.t[windows.back().end - 1], lo - pad, hi + pad};
}

/// The box and its labels: value range on the left, time range below.
std::string axes(const Frame& f) {
  return fmt::format(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#999"/>)", kLeft, kTop, kWidth - kLeft - kRight,
                     kHeight - kTop - kBottom) +
         fmt::format(
             "\n<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{:.3g}</text><text x=\"{}\" y=\"{}\" text-anchor=\"end\">{:.3g}</text>\n",
             kLeft - 4, kTop + 10, f.hi, kLeft - 4, kHeight - kBottom, f.lo) +
         fmt::format("<text x=\"{}\" y=\"{}\">t = {:.1f} s</text><text x=\"{}\" y=\"{}\" text-anchor=\"end\">{:.1f} s</text>\n", kLeft,
                     kHeight - 8, f.t0, kWidth - kRight, kHeight - 8, f.t1);
}

/// One polyline per window of `v` (times `scale`; an angle taken within pi of the measured `y`),
/// every `stride`-th sample.
std::string polylines(const ValidationRun& run, const std::vector<Window>& windows, const Frame& f, const std::vector<double>& v,
                      const std::vector<double>& y, bool angle, double scale, const char* colour, std::size_t stride) {
  std::string out;
  for (const Window& w : windows) {
    out += fmt::format(R"(<polyline fill="none" stroke="{}" stroke-width="1" points=")", colour);
    for (std::size_t k = w.begin; k < w.end; k += stride) {
      const double value = angle ? y[k] + wrap_pi(v[k] - y[k]) : v[k];
      out += fmt::format("{:.1f},{:.1f} ", f.x(run.t[k]), f.y(value * scale));
    }
    out += "\"/>\n";
  }
  return out;
}

/// Channel c over `windows`: each file's prediction, then the measured on top.
std::string plot(const ValidationRun& run, std::size_t c, const std::vector<Window>& windows) {
  const ChannelSpec& spec = kChannelSpecs[c];
  const std::vector<double>& y = run.measured[c];
  const double scale = display_scale(spec);
  const Frame f = frame_of(run, windows, y, scale);
  const std::size_t stride = std::max<std::size_t>(1, (scored_samples(windows) + kMaxPoints - 1) / kMaxPoints);
  std::string out = fmt::format("<svg width=\"{}\" height=\"{}\" xmlns=\"http://www.w3.org/2000/svg\">\n", kWidth, kHeight) + axes(f);
  for (std::size_t i = 0; i < run.files.size(); ++i)
    out += polylines(run, windows, f, run.files[i].prediction.channel[c], y, spec.angle, scale, kColours[i % std::size(kColours)], stride);
  out += polylines(run, windows, f, y, y, false, scale, "#000", stride);
  return out + "</svg>\n";
}

/// Channel c's section: the whole flight, then its first kCloseUp windows at every sample.
std::string channel_section(const ValidationRun& run, std::size_t c) {
  const std::vector<Window> first(run.windows.begin(), run.windows.begin() + std::min(kCloseUp, run.windows.size()));
  return fmt::format("<h3>{} ({})</h3>\n", kChannelSpecs[c].name, display_unit(kChannelSpecs[c])) + plot(run, c, run.windows) +
         fmt::format("<br>the first {} windows:<br>\n", first.size()) + plot(run, c, first);
}

}  // namespace

std::string validate_html(const ValidationRun& run) {
  std::string out = "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>tern validate: " + escaped(run.log) +
                    "</title>\n<style>body{font-family:sans-serif;margin:1em 2em}table{border-collapse:collapse}td,th{border:1px solid "
                    "#ccc;padding:2px 8px;text-align:right}svg text{font-size:11px}</style></head><body>\n";
  out += "<h1>tern validate: " + escaped(run.log) + "</h1>\n<pre>" + escaped(format_validate_table(run)) + "</pre>\n";
  out += "<h2>Measured and predicted, per channel</h2>\n<p>Measured in black; each file's prediction in its colour:";
  for (std::size_t i = 0; i < run.files.size(); ++i)
    out += fmt::format(R"( <span style="color:{}">[{}] {}</span>)", kColours[i % std::size(kColours)], i + 1, escaped(run.files[i].file));
  out += ". Each window starts from the log; predictions beyond the plot are drawn at its edge.</p>\n";
  for (std::size_t c = 0; c < kChannels; ++c) out += channel_section(run, c);
  return out + "</body></html>\n";
}

}  // namespace tern::core::sysid
