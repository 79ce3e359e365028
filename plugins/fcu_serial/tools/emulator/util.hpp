// emulator/util.hpp: small helpers shared by tern-fcu-emulator and tern-fcu-sil: time in
// integer ns, the monotonic clock, a sensor schedule of a rate, lists of numbers on the command line.
#pragma once

#include <chrono>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "tern_sim_aero/sensors.hpp"

namespace tern::fcu::emulator {

/// A fixed GNSS epoch (2025-11-21 00:00 UTC, ns): the fixes' Unix time is repeatable.
inline constexpr std::int64_t kUnixEpoch = 1'763'683'200'000'000'000;

inline std::int64_t mono_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

inline std::int64_t ns(double s) { return static_cast<std::int64_t>(std::llround(s * 1e9)); }

inline sim::SensorSchedule every(double hz) {
  sim::SensorSchedule s;
  s.period = ns(1.0 / hz);
  return s;
}

/// n numbers separated by ',' (or ':' if the text holds one); throws std::runtime_error naming `what`.
inline std::vector<double> numbers(const std::string& s, std::size_t n, const std::string& what) {
  std::vector<double> v;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, s.find(':') != std::string::npos ? ':' : ',');) {
    try {
      v.push_back(std::stod(item));
    } catch (const std::exception&) {
      throw std::runtime_error(what + ": '" + s + "' is not a list of numbers");
    }
  }
  if (v.size() != n) throw std::runtime_error(what + ": needs " + std::to_string(n) + " numbers, got '" + s + "'");
  return v;
}

}  // namespace tern::fcu::emulator
