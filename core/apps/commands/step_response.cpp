// Step-response figures; definitions in step_response.hpp.
#include "commands/step_response.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tern::core {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// First time the response, moving from y0 towards y_f, reaches `level` (s = sign of the
/// step); NaN if it never does.
double first_crossing(const std::vector<double>& t, const std::vector<double>& y, double level, double s) {
  for (std::size_t i = 1; i < y.size(); ++i) {
    if (s * (y[i] - level) < 0.0) continue;
    const double dy = y[i] - y[i - 1];
    const double f = dy != 0.0 ? (level - y[i - 1]) / dy : 1.0;
    return t[i - 1] + std::min(std::max(f, 0.0), 1.0) * (t[i] - t[i - 1]);
  }
  return kNaN;
}

/// Time after which |y - y_f| stays within `tol`: the band's edge crossed after the last sample
/// outside it; NaN if the last sample is outside.
double settling(const std::vector<double>& t, const std::vector<double>& y, double y_f, double tol) {
  const std::size_t n = y.size();
  if (std::abs(y[n - 1] - y_f) > tol) return kNaN;
  std::size_t i = n - 1;
  while (i > 0 && std::abs(y[i - 1] - y_f) <= tol) --i;
  if (i == 0) return t[0];
  const double e0 = std::abs(y[i - 1] - y_f), e1 = std::abs(y[i] - y_f);
  const double f = e0 != e1 ? (e0 - tol) / (e0 - e1) : 1.0;
  return t[i - 1] + f * (t[i] - t[i - 1]);
}
}  // namespace

StepMetrics step_metrics(const std::vector<double>& t, const std::vector<double>& y, double r, double band, double final_fraction) {
  if (t.size() != y.size() || t.size() < 4) throw std::invalid_argument("step_metrics: t and y need the same size, at least 4");
  for (std::size_t i = 1; i < t.size(); ++i)
    if (!(t[i] > t[i - 1])) throw std::invalid_argument("step_metrics: t must increase");
  StepMetrics m;
  m.y0 = y.front();
  const double t_tail = t.back() - final_fraction * (t.back() - t.front());
  double sum = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] >= t_tail) sum += y[i], ++count;
  m.y_final = sum / count;
  const double span = m.y_final - m.y0;
  if (span == 0.0) throw std::invalid_argument("step_metrics: the response did not move (y_f == y0)");
  const double s = span > 0.0 ? 1.0 : -1.0;
  m.rise_time = first_crossing(t, y, m.y0 + 0.9 * span, s) - first_crossing(t, y, m.y0 + 0.1 * span, s);
  double peak = 0.0;
  for (double v : y) peak = std::max(peak, s * (v - m.y_final));
  m.overshoot_pct = 100.0 * peak / std::abs(span);
  m.settling_time = settling(t, y, m.y_final, band * std::abs(span)) - t.front();
  m.steady_state_error = r - m.y_final;
  return m;
}

}  // namespace tern::core
