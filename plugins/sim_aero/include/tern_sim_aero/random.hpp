// tern_sim_aero/random.hpp: the simulated world's random engine.
#pragma once

#include <pcg_random.hpp>

namespace tern::sim {

/// The engine of every random draw in the simulated world (sensor noise and biases, turbulence,
/// gusts, the rangefinder), seeded from the mission's seed: PCG's pcg64 (M. E. O'Neill, "PCG: A
/// Family of Simple Fast Space-Efficient Statistically Good Algorithms for Random Number
/// Generation", 2014; Debian's libpcg-cpp-dev, header only). Its 16-byte state gives a 64-bit
/// draw in about a nanosecond; std::mt19937_64's 2.5-kB state took several (with Boost's
/// ziggurat normal: 9.7 against 3.8 ns a draw on this project's machine, and a default flight
/// draws ~8700 a simulated second). Its output is fixed by its code: the same seed gives the
/// same flight on every machine and standard library.
using Rng = pcg64;

}  // namespace tern::sim
