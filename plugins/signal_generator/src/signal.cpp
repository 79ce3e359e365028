// The waveforms of signal.hpp. ROSplane's formulas (signal_generator.cpp, get_*_signal) are
// written there around a centre value with a half-magnitude amplitude; here each shape is on
// [0, 1] (doublet [-1, 1]) and the plugin scales it.
#include "tern/signal_generator/signal.hpp"

#include <array>
#include <cmath>
#include <utility>
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

}  // namespace tern::signal
