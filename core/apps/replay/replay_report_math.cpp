// The replay report's arithmetic: brackets and linear interpolation in time, angle wrapping, RMS
// and largest error, percentiles.
#include <algorithm>
#include <cmath>

#include "replay/replay_report_parts.hpp"

namespace tern::core::replay_report {

double wrap_pi(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  return (a < 0.0 ? a + 2.0 * M_PI : a) - M_PI;
}

std::optional<Bracket> bracket(const std::vector<double>& t, double tq, double max_gap_s) {
  if (t.empty() || !(tq >= t.front() && tq <= t.back())) return std::nullopt;
  const auto it = std::upper_bound(t.begin(), t.end(), tq);
  if (it == t.end()) return Bracket{t.size() - 1, 0.0};  // tq == t.back()
  const auto k = static_cast<std::size_t>(it - t.begin()) - 1;
  const double dt = t[k + 1] - t[k];
  if (tq == t[k]) return Bracket{k, 0.0};
  if (!(dt <= max_gap_s)) return std::nullopt;
  return Bracket{k, (tq - t[k]) / dt};
}

double lerp(const std::vector<double>& v, const Bracket& b, bool angle) {
  if (b.f == 0.0) return v[b.k];
  const double d = angle ? wrap_pi(v[b.k + 1] - v[b.k]) : v[b.k + 1] - v[b.k];
  const double x = v[b.k] + b.f * d;
  return angle ? wrap_pi(x) : x;
}

double interpolate(const std::vector<double>& t, const std::vector<double>& v, double tq, double max_gap_s, bool angle) {
  const auto b = bracket(t, tq, max_gap_s);
  return b ? lerp(v, *b, angle) : NAN;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const double x = p * static_cast<double>(v.size() - 1);
  const auto k = static_cast<std::size_t>(std::floor(x));
  return k + 1 < v.size() ? v[k] + (x - static_cast<double>(k)) * (v[k + 1] - v[k]) : v[k];
}

double median(const std::vector<double>& v) { return percentile(v, 0.5); }

std::pair<std::size_t, std::size_t> index_range(const std::vector<double>& t, double start, double end) {
  const auto first = std::lower_bound(t.begin(), t.end(), start);
  const auto last = std::upper_bound(first, t.end(), end);
  return {static_cast<std::size_t>(first - t.begin()), static_cast<std::size_t>(last - t.begin())};
}

void ErrorSum::add(double e) {
  if (std::isnan(e)) return;
  sum += e;
  sum2 += e * e;
  max = std::max(max, std::fabs(e));
  ++n;
}

ErrorFigure ErrorSum::figure(std::string unit, std::string rule) const {
  ErrorFigure f;
  f.unit = std::move(unit);
  f.rule = std::move(rule);
  f.samples = n;
  if (n > 0) {
    f.rms = std::sqrt(sum2 / static_cast<double>(n));
    f.max = max;
    f.mean = sum / static_cast<double>(n);
  }
  return f;
}

}  // namespace tern::core::replay_report
