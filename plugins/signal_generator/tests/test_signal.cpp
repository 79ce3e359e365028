// The waveforms of signal.hpp, alone.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

#include "tern/math.hpp"
#include "tern/signal_generator/signal.hpp"

using namespace tern::signal;

TEST_CASE("every waveform starts at 0 and is 0 before its start") {
  for (auto w : {Waveform::step, Waveform::square, Waveform::sine, Waveform::triangle, Waveform::sawtooth, Waveform::doublet}) {
    CHECK(waveform(w, 0.0, 4.0) == doctest::Approx(0.0));
    CHECK(waveform(w, -1.0, 4.0) == 0.0);
  }
}

TEST_CASE("step and square have their first edge at half a period; the square repeats") {
  CHECK(waveform(Waveform::step, 1.99, 4.0) == 0.0);
  CHECK(waveform(Waveform::step, 2.0, 4.0) == 1.0);
  CHECK(waveform(Waveform::step, 100.0, 4.0) == 1.0);
  CHECK(waveform(Waveform::square, 1.99, 4.0) == 0.0);
  CHECK(waveform(Waveform::square, 3.99, 4.0) == 1.0);
  CHECK(waveform(Waveform::square, 4.01, 4.0) == 0.0);
  CHECK(waveform(Waveform::square, 6.01, 4.0) == 1.0);
}

TEST_CASE("sine, triangle and sawtooth peak where ROSplane's do") {
  CHECK(waveform(Waveform::sine, 2.0, 4.0) == doctest::Approx(1.0));
  CHECK(waveform(Waveform::sine, 1.0, 4.0) == doctest::Approx(0.5));
  CHECK(waveform(Waveform::triangle, 2.0, 4.0) == doctest::Approx(1.0));
  CHECK(waveform(Waveform::triangle, 3.0, 4.0) == doctest::Approx(0.5));
  CHECK(waveform(Waveform::sawtooth, 3.0, 4.0) == doctest::Approx(0.75));
  CHECK(waveform(Waveform::sawtooth, 4.5, 4.0) == doctest::Approx(0.125));
}

TEST_CASE("a doublet is one pulse up, one down, then nothing") {
  CHECK(waveform(Waveform::doublet, 1.0, 4.0) == 0.0);
  CHECK(waveform(Waveform::doublet, 3.0, 4.0) == 1.0);
  CHECK(waveform(Waveform::doublet, 5.0, 4.0) == -1.0);
  CHECK(waveform(Waveform::doublet, 6.0, 4.0) == 0.0);
  CHECK(waveform(Waveform::doublet, 60.0, 4.0) == 0.0);
}

TEST_CASE("names round-trip; unknown names are refused") {
  for (auto l : {Loop::roll, Loop::pitch, Loop::course, Loop::altitude, Loop::airspeed}) CHECK(loop_from_name(loop_name(l)) == l);
  CHECK(!loop_from_name("yaw_rate"));
  CHECK(!waveform_from_name("chirp"));
  CHECK(command_symbol(Loop::altitude) == "h_c");
  CHECK(loop_unit(Loop::airspeed) == "m/s");
}

// ---- excitation manoeuvres ----

namespace {
/// Zero crossings of f on [a, b] sampled every dt.
int zero_crossings(const std::function<double(double)>& f, double a, double b, double dt) {
  int n = 0;
  double prev = f(a);
  for (double t = a + dt; t <= b; t += dt) {
    const double v = f(t);
    if ((prev < 0.0 && v >= 0.0) || (prev >= 0.0 && v < 0.0)) ++n;
    prev = v;
  }
  return n;
}
}  // namespace

TEST_CASE("chirp: logarithmic sweep from f_start to f_stop, its zero crossings follow the instantaneous frequency") {
  const Chirp c{0.2, 3.0, 30.0, 3.0, 2.0};
  c.validate();
  CHECK(c.frequency_hz(0.0) == doctest::Approx(0.2));
  CHECK(c.frequency_hz(30.0) == doctest::Approx(3.0));
  CHECK(c.frequency_hz(15.0) == doctest::Approx(std::sqrt(0.2 * 3.0)));  // the geometric mean at half time: logarithmic
  // The phase is 2 pi times the integral of f: twice that many zero crossings in each window.
  const auto cycles = [&](double t) { return 0.2 * 30.0 / std::log(15.0) * (std::exp(std::log(15.0) * t / 30.0) - 1.0); };
  for (const auto& [a, b] : {std::pair{5.0, 10.0}, std::pair{15.0, 20.0}, std::pair{22.0, 27.0}}) {
    const int n = zero_crossings([&](double t) { return c.value(t); }, a, b, 1e-4);
    CHECK(std::abs(n - 2.0 * (cycles(b) - cycles(a))) <= 1.0);
  }
  double peak = 0.0;
  for (double t = 0.0; t <= 30.0; t += 1e-3) peak = std::max(peak, std::abs(c.value(t)));
  CHECK(peak <= 1.0);
  CHECK(peak > 0.99);
  // Fades: 0 at both ends, a half-cosine window inside t_rec.
  CHECK(c.value(0.0) == 0.0);
  CHECK(c.window(1.5) == doctest::Approx(0.5));
  CHECK(c.window(29.0) == doctest::Approx(0.5));
  CHECK(c.window(15.0) == 1.0);
  CHECK(c.value(30.5) == 0.0);
  CHECK(c.value(-0.1) == 0.0);
}

TEST_CASE("chirp: bad parameters are one line naming the parameter and its value") {
  CHECK_THROWS_WITH_AS((Chirp{2.0, 1.0, 20.0, 1.0, 1.0}.validate()), "f_stop_hz 1 must be above f_start_hz 2 (Hz)", std::invalid_argument);
  CHECK_THROWS_WITH_AS((Chirp{0.5, 1.0, -3.0, 0.0, 0.0}.validate()), "t_rec -3 must be > 0 s", std::invalid_argument);
  CHECK_THROWS_WITH_AS((Chirp{0.5, 1.0, 10.0, -1.0, 0.0}.validate()), "t_fade_in -1 must be >= 0 s", std::invalid_argument);
  CHECK_THROWS_AS((Chirp{0.5, 1.0, 10.0, 6.0, 6.0}.validate()), std::invalid_argument);
}

TEST_CASE("multisine: interleaved harmonics, orthogonal across axes over the record, peak 1, low peak factor") {
  const double T = 20.0;
  const Multisine a(0.2, 2.0, T, 3, 0), b(0.2, 2.0, T, 3, 1), c(0.2, 2.0, T, 3, 2);
  // 0.2..2 Hz over 20 s: harmonics 4..40, dealt in turn.
  CHECK(a.harmonics().front() == 4);
  CHECK(b.harmonics().front() == 5);
  CHECK(c.harmonics().front() == 6);
  for (int k : a.harmonics()) {
    CHECK(std::find(b.harmonics().begin(), b.harmonics().end(), k) == b.harmonics().end());
    CHECK(std::find(c.harmonics().begin(), c.harmonics().end(), k) == c.harmonics().end());
  }
  // Inner products over the record (uniform samples, more than twice the highest harmonic).
  const int n = 4000;
  double aa = 0, bb = 0, cc = 0, ab = 0, ac = 0, bc = 0, peak = 0;
  for (int i = 0; i < n; ++i) {
    const double t = T * i / n, x = a.value(t), y = b.value(t), z = c.value(t);
    aa += x * x, bb += y * y, cc += z * z, ab += x * y, ac += x * z, bc += y * z;
    peak = std::max({peak, std::abs(x), std::abs(y), std::abs(z)});
  }
  CHECK(std::abs(ab) / std::sqrt(aa * bb) < 1e-8);
  CHECK(std::abs(ac) / std::sqrt(aa * cc) < 1e-8);
  CHECK(std::abs(bc) / std::sqrt(bb * cc) < 1e-8);
  CHECK(peak <= 1.0);
  CHECK(peak > 0.99);
  // In phase, M equal harmonics peak at sqrt(M) times a sine's peak factor; Schroeder's phases keep it low.
  const double M = static_cast<double>(a.harmonics().size());
  CHECK(a.peak_factor() < 0.6 * std::sqrt(M));
  CHECK(a.peak_factor() < 2.0);
  // Its spectrum: power at its own harmonics, none at the others' (one DFT bin per harmonic).
  const auto bin = [&](const Multisine& m, int k) {
    double re = 0, im = 0;
    for (int i = 0; i < n; ++i) {
      const double t = T * i / n, arg = 2.0 * tern::kPi * k * t / T;
      re += m.value(t) * std::cos(arg), im += m.value(t) * std::sin(arg);
    }
    return std::hypot(re, im) / n;
  };
  CHECK(bin(a, 4) > 0.05);
  CHECK(bin(a, 5) < 1e-8);
  CHECK(bin(b, 5) > 0.05);
  CHECK(bin(b, 6) < 1e-8);
  CHECK(a.value(T) == 0.0);
}

TEST_CASE("multisine: a band with too few harmonics for the axes is refused, naming the band") {
  CHECK_THROWS_AS(Multisine(1.0, 1.05, 10.0, 2, 1), std::invalid_argument);
  CHECK_THROWS_AS(Multisine(2.0, 1.0, 10.0, 1, 0), std::invalid_argument);
  CHECK_NOTHROW(Multisine(1.0, 1.1, 10.0, 2, 1));
}

TEST_CASE("3-2-1-1 and doublet: pulse widths and signs") {
  const double Tp = 0.5;
  CHECK(input_3211(-0.01, Tp) == 0.0);
  CHECK(input_3211(0.0, Tp) == 1.0);
  CHECK(input_3211(1.49, Tp) == 1.0);
  CHECK(input_3211(1.5, Tp) == -1.0);
  CHECK(input_3211(2.49, Tp) == -1.0);
  CHECK(input_3211(2.5, Tp) == 1.0);
  CHECK(input_3211(2.99, Tp) == 1.0);
  CHECK(input_3211(3.0, Tp) == -1.0);
  CHECK(input_3211(3.49, Tp) == -1.0);
  CHECK(input_3211(3.5, Tp) == 0.0);
  // Widths from the sampled signal: 3, 2, 1, 1 pulses.
  std::vector<int> runs{1};
  double prev = input_3211(0.0, Tp);
  for (int i = 1; i < 350; ++i) {
    const double v = input_3211(i * 0.01, Tp);
    if (v == prev)
      ++runs.back();
    else
      runs.push_back(1);
    prev = v;
  }
  CHECK(runs == std::vector<int>{150, 100, 50, 50});
  CHECK(input_doublet(0.2, Tp) == 1.0);
  CHECK(input_doublet(0.7, Tp) == -1.0);
  CHECK(input_doublet(1.0, Tp) == 0.0);
}
