// core/apps/campaign/counter_rng.hpp: counter-based random numbers for campaigns.
//
// Every number a campaign draws is a pure function of (campaign seed, flight index, stream,
// component): SplitMix64's finaliser (tern::splitmix64 of tern/random.hpp) applied to the key
// words in turn. No generator state is carried from one flight to the next, so flight k draws the same
// values whatever the engine, the order or the number of workers. A stream is the FNV-1a hash of
// the drawn column's name ("sim.wind.speed"), so adding a dispersion changes no other column.
#pragma once

#include <cmath>
#include <cstdint>
#include <string_view>

#include "tern/random.hpp"

namespace tern::campaign {

/// 64-bit FNV-1a of a name (a stream id).
constexpr std::uint64_t stream_id(std::string_view name) {
  Fnv1a f{Fnv1a::kOffsetBasis};
  f.chars(name);
  return f.h;
}

/// The random word for (seed, flight, stream, component).
constexpr std::uint64_t draw_word(std::uint64_t seed, std::uint64_t flight, std::uint64_t stream, std::uint64_t component = 0) {
  return splitmix64(splitmix64(splitmix64(splitmix64(seed) ^ flight) ^ stream) ^ component);
}

/// Uniform in [0, 1): the top 53 bits of the word.
inline double draw_uniform(std::uint64_t seed, std::uint64_t flight, std::uint64_t stream, std::uint64_t component = 0) {
  return static_cast<double>(draw_word(seed, flight, stream, component) >> 11) * 0x1.0p-53;
}

/// Standard normal (Box-Muller on components 2c and 2c+1; u1 in (0, 1]).
inline double draw_normal(std::uint64_t seed, std::uint64_t flight, std::uint64_t stream, std::uint64_t component = 0) {
  const double u1 = 1.0 - draw_uniform(seed, flight, stream, 2 * component);
  const double u2 = draw_uniform(seed, flight, stream, 2 * component + 1);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

/// The seed of flight `flight` of a campaign seeded `seed` (the flight's mission `seed:`).
constexpr std::uint64_t flight_seed(std::uint64_t seed, std::uint64_t flight) { return draw_word(seed, flight, stream_id("seed")); }

}  // namespace tern::campaign
