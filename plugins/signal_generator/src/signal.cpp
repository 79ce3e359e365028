// The waveforms of signal.hpp. ROSplane's formulas (signal_generator.cpp, get_*_signal) are
// written there around a centre value with a half-magnitude amplitude; here each shape is on
// [0, 1] (doublet [-1, 1]) and the plugin scales it.
#include "tern/signal_generator/signal.hpp"

#include <array>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <fmt/format.h>

#include "tern/math.hpp"

namespace tern::signal {

namespace {
using tern::kPi;

/// Fraction of the current period elapsed, in [0, 1).
double phase(double t, double period) { return t / period - std::floor(t / period); }

template <class E, std::size_t N>
std::optional<E> from_name(const std::array<std::pair<std::string_view, E>, N>& table, std::string_view name) {
  for (const auto& [n, e] : table)
    if (n == name) return e;
  return std::nullopt;
}

constexpr std::array<std::pair<std::string_view, Waveform>, 6> kWaveforms{{{"step", Waveform::step},
                                                                           {"square", Waveform::square},
                                                                           {"sine", Waveform::sine},
                                                                           {"triangle", Waveform::triangle},
                                                                           {"sawtooth", Waveform::sawtooth},
                                                                           {"doublet", Waveform::doublet}}};
constexpr std::array<std::pair<std::string_view, Loop>, 5> kLoops{
    {{"roll", Loop::roll}, {"pitch", Loop::pitch}, {"course", Loop::course}, {"altitude", Loop::altitude}, {"airspeed", Loop::airspeed}}};
}  // namespace

double waveform(Waveform w, double t, double period) {
  if (t < 0.0) return 0.0;
  const double x = phase(t, period);
  switch (w) {
    case Waveform::step: return t < period / 2.0 ? 0.0 : 1.0;
    case Waveform::square: return x < 0.5 ? 0.0 : 1.0;
    case Waveform::sine: return (1.0 - std::cos(2.0 * kPi * x)) / 2.0;
    case Waveform::triangle: return x < 0.5 ? 2.0 * x : 2.0 * (1.0 - x);
    case Waveform::sawtooth: return x;
    case Waveform::doublet:
      if (t < period / 2.0 || t >= 1.5 * period) return 0.0;
      return t < period ? 1.0 : -1.0;
  }
  return 0.0;
}

std::optional<Waveform> waveform_from_name(std::string_view name) { return from_name(kWaveforms, name); }
std::optional<Loop> loop_from_name(std::string_view name) { return from_name(kLoops, name); }

std::optional<Reference> reference_from_name(std::string_view name) {
  if (name == "command") return Reference::command;
  if (name == "absolute") return Reference::absolute;
  return std::nullopt;
}

std::string_view loop_name(Loop l) {
  for (const auto& [n, e] : kLoops)
    if (e == l) return n;
  return "roll";
}

std::string_view command_symbol(Loop l) {
  switch (l) {
    case Loop::roll: return "phi_c";
    case Loop::pitch: return "theta_c";
    case Loop::course: return "chi_c";
    case Loop::altitude: return "h_c";
    case Loop::airspeed: return "Va_c";
  }
  return "phi_c";
}

std::string_view loop_unit(Loop l) {
  switch (l) {
    case Loop::roll:
    case Loop::pitch:
    case Loop::course: return "rad";
    case Loop::altitude: return "m";
    case Loop::airspeed: return "m/s";
  }
  return "";
}

// ---- excitation manoeuvres ------------------------------------------------------------------

void Chirp::validate() const {
  if (!(f_start_hz > 0.0)) throw std::invalid_argument(fmt::format("f_start_hz {} must be > 0 Hz", f_start_hz));
  if (!(f_stop_hz > f_start_hz))
    throw std::invalid_argument(fmt::format("f_stop_hz {} must be above f_start_hz {} (Hz)", f_stop_hz, f_start_hz));
  if (!(t_rec > 0.0)) throw std::invalid_argument(fmt::format("t_rec {} must be > 0 s", t_rec));
  if (!(t_fade_in >= 0.0)) throw std::invalid_argument(fmt::format("t_fade_in {} must be >= 0 s", t_fade_in));
  if (!(t_fade_out >= 0.0)) throw std::invalid_argument(fmt::format("t_fade_out {} must be >= 0 s", t_fade_out));
  if (t_fade_in + t_fade_out > t_rec)
    throw std::invalid_argument(fmt::format("t_fade_in {} + t_fade_out {} exceed t_rec {} (s)", t_fade_in, t_fade_out, t_rec));
}

double Chirp::window(double t) const {
  if (t < 0.0 || t > t_rec) return 0.0;
  if (t < t_fade_in) return 0.5 - 0.5 * std::cos(kPi * t / t_fade_in);
  if (t > t_rec - t_fade_out) return 0.5 - 0.5 * std::cos(kPi * (t_rec - t) / t_fade_out);
  return 1.0;
}

double Chirp::frequency_hz(double t) const {
  const double B = std::log(f_stop_hz / f_start_hz);
  return f_start_hz * std::exp(B * std::clamp(t, 0.0, t_rec) / t_rec);
}

double Chirp::value(double t) const {
  if (t < 0.0 || t > t_rec) return 0.0;
  const double B = std::log(f_stop_hz / f_start_hz);
  const double omega_0 = 2.0 * kPi * f_start_hz;
  return window(t) * std::sin(omega_0 * t_rec / B * (std::exp(B * t / t_rec) - 1.0));
}

Multisine::Multisine(double f_start_hz, double f_stop_hz, double t_rec, int n_axes, int axis) : t_rec_(t_rec) {
  if (!(t_rec > 0.0)) throw std::invalid_argument(fmt::format("t_rec {} must be > 0 s", t_rec));
  if (!(f_start_hz >= 0.0)) throw std::invalid_argument(fmt::format("f_start_hz {} must be >= 0 Hz", f_start_hz));
  if (!(f_stop_hz >= f_start_hz))
    throw std::invalid_argument(fmt::format("f_stop_hz {} must not be below f_start_hz {} (Hz)", f_stop_hz, f_start_hz));
  if (n_axes < 1 || axis < 0 || axis >= n_axes)
    throw std::invalid_argument(fmt::format("multisine axis {} of {}: out of range", axis, n_axes));
  const int k_lo = std::max(1, static_cast<int>(std::ceil(f_start_hz * t_rec - 1e-9)));
  const int k_hi = static_cast<int>(std::floor(f_stop_hz * t_rec + 1e-9));
  for (int k = k_lo + axis; k <= k_hi; k += n_axes) k_.push_back(k);
  if (k_.empty())
    throw std::invalid_argument(
        fmt::format("f_start_hz {} .. f_stop_hz {} over t_rec {} s holds {} harmonics of 1/t_rec, fewer than "
                    "the {} axes excited at once: widen the band or lengthen t_rec",
                    f_start_hz, f_stop_hz, t_rec, std::max(0, k_hi - k_lo + 1), n_axes));
  const double M = static_cast<double>(k_.size());
  for (std::size_t m = 1; m <= k_.size(); ++m) phase_.push_back(-kPi * static_cast<double>(m * (m - 1)) / M);
  // Peak over the record: a grid of 16 samples per period of the highest harmonic, then a
  // golden-section search on each of the grid's local maxima of |sum| near its peak (the sum is
  // smooth: one maximum between two grid neighbours).
  const int n = std::max(256, 16 * k_.back());
  const double dt = t_rec / n;
  std::vector<double> r(static_cast<std::size_t>(n));
  double coarse = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    r[static_cast<std::size_t>(i)] = raw(dt * i);
    coarse = std::max(coarse, std::abs(r[static_cast<std::size_t>(i)]));
    sum2 += r[static_cast<std::size_t>(i)] * r[static_cast<std::size_t>(i)];
  }
  double peak = coarse;
  const auto at = [&](int i) { return std::abs(r[static_cast<std::size_t>((i + n) % n)]); };
  const double golden = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int i = 0; i < n; ++i) {
    if (at(i) < 0.95 * coarse || at(i) < at(i - 1) || at(i) < at(i + 1)) continue;
    double a = dt * (i - 1), b = dt * (i + 1);
    for (int it = 0; it < 60; ++it) {
      const double c = b - golden * (b - a), d = a + golden * (b - a);
      if (std::abs(raw(c)) > std::abs(raw(d)))
        b = d;
      else
        a = c;
    }
    peak = std::max(peak, std::abs(raw((a + b) / 2.0)));
  }
  scale_ = 1.0 / peak;
  peak_factor_ = peak / std::sqrt(2.0 * sum2 / n);
}

double Multisine::raw(double t) const {
  double s = 0.0;
  for (std::size_t m = 0; m < k_.size(); ++m) s += std::cos(2.0 * kPi * k_[m] * t / t_rec_ + phase_[m]);
  return s;
}

double Multisine::value(double t) const {
  if (t < 0.0 || t >= t_rec_) return 0.0;
  return std::clamp(scale_ * raw(t), -1.0, 1.0);
}

double input_3211(double t, double T_p) {
  if (t < 0.0 || t >= 7.0 * T_p) return 0.0;
  if (t < 3.0 * T_p) return 1.0;
  if (t < 5.0 * T_p) return -1.0;
  if (t < 6.0 * T_p) return 1.0;
  return -1.0;
}

double input_doublet(double t, double T_p) {
  if (t < 0.0 || t >= 2.0 * T_p) return 0.0;
  return t < T_p ? 1.0 : -1.0;
}

}  // namespace tern::signal
