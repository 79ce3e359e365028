// core/apps/sysid/spectra.cpp: the samples' stretches, trim windows and their statistics (spectra.hpp).
#include "sysid/spectra.hpp"

#include <algorithm>
#include <cmath>

namespace tern::core::sysid {

Layout layout_of(const AeroSamples& a, double window_s, double min_segment_s) {
  Layout L;
  std::size_t begin = 0;
  for (std::size_t k = 1; k <= a.size(); ++k) {
    if (k < a.size() && a.source[k] == a.source[k - 1] + 1) continue;
    if (a.t[k - 1] - a.t[begin] >= min_segment_s) {
      // pieces of at most kMaxSegment (equal lengths): the batches of the scatter bound
      const auto pieces = static_cast<std::size_t>(std::ceil((a.t[k - 1] - a.t[begin]) / kMaxSegment));
      for (std::size_t i = 0; i < pieces; ++i)
        L.segments.emplace_back(begin + (k - begin) * i / pieces, begin + (k - begin) * (i + 1) / pieces);
    }
    // trim windows over every stretch, short ones too
    for (std::size_t w = begin; w < k;) {
      std::vector<std::size_t> idx;
      for (; w < k && a.t[w] - a.t[idx.empty() ? w : idx.front()] < window_s; ++w) idx.push_back(w);
      if (a.t[idx.back()] - a.t[idx.front()] >= 0.75 * window_s) L.windows.push_back(std::move(idx));
    }
    begin = k;
  }
  return L;
}

Col window_means(const Col& x, const Layout& L) {
  Col m;
  for (const auto& w : L.windows) {
    double s = 0.0;
    for (const std::size_t k : w) s += x[k];
    m.push_back(s / static_cast<double>(w.size()));
  }
  return m;
}

Col detrended(const Col& x, const Layout& L) {
  Col d(x.size(), 0.0);
  const Col m = window_means(x, L);
  for (std::size_t i = 0; i < L.windows.size(); ++i)
    for (const std::size_t k : L.windows[i]) d[k] = x[k] - m[i];
  return d;
}

double rms(const Col& x) {
  double s = 0.0;
  for (const double v : x) s += v * v;
  return x.empty() ? 0.0 : std::sqrt(s / static_cast<double>(x.size()));
}

double peak(const Col& x) {
  double m = 0.0;
  for (const double v : x) m = std::max(m, std::abs(v));
  return m;
}

double stddev(const Col& x) {
  double m = 0.0;
  for (const double v : x) m += v;
  m /= static_cast<double>(x.size());
  double s = 0.0;
  for (const double v : x) s += (v - m) * (v - m);
  return std::sqrt(s / static_cast<double>(x.size()));
}

}  // namespace tern::core::sysid
