// tern/fnv1a.hpp: the 64-bit FNV-1a hash (Fowler, Noll & Vo; the offset basis and prime of
// draft-eastlake-fnv), fed piece by piece. Not a cryptographic hash. Used for the messages'
// layout fingerprints (reflect.hpp), derived seeds (random.hpp), the campaigns' stream ids (from
// the true offset basis) and the plugin libraries' identity in summary.json. Header-only, constexpr.
#pragma once

#include <cstdint>
#include <string_view>

namespace tern {

struct Fnv1a {
  /// FNV's 64-bit offset basis (14695981039346656037).
  static constexpr std::uint64_t kOffsetBasis = 0xcbf29ce484222325ULL;
  /// The basis tern's layout fingerprints and derived seeds start from: the offset basis's first
  /// 19 of 20 decimal digits, a slip kept on purpose: every plugin's handshake fingerprint (plugins
  /// built earlier) and every flight's instance seeds rest on it.
  static constexpr std::uint64_t kTernBasis = 1469598103934665603ULL;
  static constexpr std::uint64_t kPrime = 0x100000001b3ULL;
  std::uint64_t h = kTernBasis;
  /// The bytes of s, as they are (FNV-1a of a whole string when fed once).
  constexpr void chars(std::string_view s) {
    for (char c : s) byte(static_cast<unsigned char>(c));
  }
  /// A field: the bytes of s, then a 0xff separator (so "ab","c" and "a","bc" differ).
  constexpr void bytes(std::string_view s) {
    chars(s);
    byte(0xffu);
  }
  /// The 8 bytes of v, least significant first.
  constexpr void number(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) byte((v >> (8 * i)) & 0xffu);
  }
  constexpr void byte(std::uint64_t b) {
    h ^= b;
    h *= kPrime;
  }
};

}  // namespace tern
