// tern/random.hpp: seed derivation shared by the host, the fleets and the campaigns.
//
// splitmix64 is SplitMix64's output function (Steele, Lea & Flood, "Fast splittable pseudorandom
// number generators", OOPSLA 2014; the constants of Vigna's splitmix64.c): a bijective mixer of a
// 64-bit word. The host derives each instance's seed with it (Context::seed()), the campaigns
// their counter-based draws (core/apps/campaign/counter_rng.hpp). Header-only, constexpr.
#pragma once

#include <cstdint>
#include <string_view>

#include "tern/fnv1a.hpp"

namespace tern {

/// SplitMix64's output of x + the golden gamma 0x9e3779b97f4a7c15: equal inputs give equal
/// words, nearby inputs unrelated ones. Not a cryptographic hash.
constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// The seed of a part named `name` of something seeded `seed`: splitmix64(seed ^ h), h the FNV-1a
/// of name's bytes and a 0xff separator (fnv1a.hpp Fnv1a::bytes). An instance's Context::seed
/// (name: the instance's), a fleet vehicle's flight seed (the vehicle's), the coordination's.
constexpr std::uint64_t derive_seed(std::uint64_t seed, std::string_view name) {
  Fnv1a f;
  f.bytes(name);
  return splitmix64(seed ^ f.h);
}

}  // namespace tern
