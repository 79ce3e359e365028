// tern/random.hpp: seed derivation shared by the host and the campaigns.
//
// splitmix64 is SplitMix64's output function (Steele, Lea & Flood, "Fast splittable pseudorandom
// number generators", OOPSLA 2014; the constants of Vigna's splitmix64.c): a bijective mixer of a
// 64-bit word. The host derives each instance's seed with it (Context::seed()), the campaigns
// their counter-based draws (core/apps/campaign/counter_rng.hpp). Header-only, constexpr.
#pragma once

#include <cstdint>

namespace tern {

/// SplitMix64's output of x + the golden gamma 0x9e3779b97f4a7c15: equal inputs give equal
/// words, nearby inputs unrelated ones. Not a cryptographic hash.
constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

}  // namespace tern
