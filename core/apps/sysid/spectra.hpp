// core/apps/sysid/spectra.hpp: the identification's samples cut up (identify.hpp): the airborne
// stretches in pieces of at most kMaxSegment (the batches of the scatter bound, jackknife.hpp), the
// trim windows in them, and each signal's frequency-domain rows over the pieces (Spectra).
#pragma once

#include <cstddef>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "sysid/aero_samples.hpp"
#include "sysid/regression.hpp"

namespace tern::core::sysid {

using Col = std::vector<double>;

/// The airborne stretches (consecutive samples of the series) and the trim windows in them.
struct Layout {
  std::vector<std::pair<std::size_t, std::size_t>> segments;  ///< [begin, end) of the samples
  std::vector<std::vector<std::size_t>> windows;              ///< samples of each trim window
};

/// s: the longest piece of an airborne stretch transformed at once (a longer stretch is cut into
/// equal pieces): the frequency-domain rows' batches, whose estimates' scatter bounds the error.
constexpr double kMaxSegment = 120.0;

Layout layout_of(const AeroSamples& a, double window_s, double min_segment_s);
/// The trim windows' means of x, one per window.
Col window_means(const Col& x, const Layout& L);
/// x less its trim-window means (samples outside every window: 0).
Col detrended(const Col& x, const Layout& L);
double rms(const Col& x);
double peak(const Col& x);
double stddev(const Col& x);

/// The frequency-domain rows of every signal: each segment at the multiples of 1/T in the band.
class Spectra {
 public:
  Spectra(const AeroSamples& a, const Layout& L, double lo, double hi) : a_(a), L_(L), lo_(lo), hi_(hi) {
    Eigen::Index at = 0;
    for (const auto& [b, e] : L_.segments) {
      const Eigen::Index n = static_cast<Eigen::Index>(frequencies(b, e).size());
      rows_.emplace_back(at, n);
      at += n;
    }
  }
  /// (first row, rows) of each segment's frequencies in every spectrum.
  const std::vector<std::pair<Eigen::Index, Eigen::Index>>& segment_rows() const { return rows_; }
  /// The frequencies (Hz) of segment i's rows.
  Col segment_frequencies(std::size_t i) const { return frequencies(L_.segments[i].first, L_.segments[i].second); }
  /// The frequency (Hz) of every row, in the spectra's row order.
  Col row_frequencies() const {
    Col f;
    for (const auto& [b, e] : L_.segments) {
      const Col fi = frequencies(b, e);
      f.insert(f.end(), fi.begin(), fi.end());
    }
    return f;
  }
  /// A spectrum made in the frequency domain (an instrument), served as `of(*key)` until forget(key):
  /// the cache is keyed by address, so a key must be forgotten before it goes out of scope.
  void put(const Col* key, Eigen::VectorXcd spectrum) { cache_[key] = std::move(spectrum); }
  void forget(const Col* key) { cache_.erase(key); }
  const Eigen::VectorXcd& of(const Col& x) {
    auto it = cache_.find(&x);
    if (it != cache_.end()) return it->second;
    std::vector<Eigen::VectorXcd> parts;
    Eigen::Index n = 0;
    for (const auto& [b, e] : L_.segments) {
      const Col t(a_.t.begin() + static_cast<std::ptrdiff_t>(b), a_.t.begin() + static_cast<std::ptrdiff_t>(e));
      const Col v(x.begin() + static_cast<std::ptrdiff_t>(b), x.begin() + static_cast<std::ptrdiff_t>(e));
      parts.push_back(fourier(v, t, frequencies(b, e)));
      n += parts.back().size();
    }
    Eigen::VectorXcd all(n);
    Eigen::Index at = 0;
    for (const auto& p : parts) all.segment(at, p.size()) = p, at += p.size();
    return cache_.emplace(&x, std::move(all)).first->second;
  }

 private:
  /// The multiples of 1/T in the band, T the segment's length.
  Col frequencies(std::size_t b, std::size_t e) const {
    const double T = a_.t[e - 1] - a_.t[b];
    Col f;
    for (int m = static_cast<int>(std::ceil(lo_ * T)); m / T <= hi_; ++m) f.push_back(m / T);
    return f;
  }
  const AeroSamples& a_;
  const Layout& L_;
  double lo_, hi_;
  std::map<const Col*, Eigen::VectorXcd> cache_;
  std::vector<std::pair<Eigen::Index, Eigen::Index>> rows_;
};

}  // namespace tern::core::sysid
