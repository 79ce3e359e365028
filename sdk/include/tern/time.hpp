// tern/time.hpp: flight time as integer nanoseconds.
//
// Every message stamp and every scheduler instant is a tern::Nanos: signed 64-bit nanoseconds of
// flight time since the host started the flight (t = 0 at the first tick). Integer time keeps
// schedules exact (400 Hz is exactly 2'500'000 ns) and logs bit-identical between runs.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace tern {

using Nanos = std::int64_t;

inline constexpr Nanos kNanosPerSecond = 1'000'000'000;

/// Nanoseconds -> seconds (double), correctly rounded for |t| < 2^53 ns (about 104 days).
constexpr double to_seconds(Nanos t) { return static_cast<double>(t) / 1e9; }

/// Seconds -> nanoseconds, rounded to the nearest nanosecond.
inline Nanos from_seconds(double s) { return static_cast<Nanos>(std::llround(s * 1e9)); }

/// Period in ns of a rate in Hz. Throws std::invalid_argument unless the rate is finite, > 0 and
/// its period is a whole number of nanoseconds (e.g. 400 Hz -> 2'500'000 ns; 390 Hz is refused:
/// 2'564'102.56 ns).
inline Nanos period_from_hz(double hz) {
  if (!(hz > 0.0) || !std::isfinite(hz)) {
    throw std::invalid_argument("rate must be a finite number > 0 Hz, got " + std::to_string(hz));
  }
  const double p = 1e9 / hz;
  const double r = std::round(p);
  if (r < 1.0 || std::fabs(p - r) > 1e-3) {
    throw std::invalid_argument("rate " + std::to_string(hz) + " Hz has no whole-nanosecond period (1e9/rate = " + std::to_string(p) +
                                " ns)");
  }
  return static_cast<Nanos>(r);
}

}  // namespace tern
