// tern/mavlink/fields.hpp: a MAVLink payload's fields as bytes: little-endian copies of numbers and
// arrays at their wire offsets (used by the message structs sdk/mavlink/generate.py writes), and
// the char[N] text fields as strings. Plain C++, header-only; the host must be little-endian.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace tern::mavlink {

static_assert(std::endian::native == std::endian::little, "the MAVLink packing helpers assume a little-endian host");

namespace detail {
template <class T>
inline void put(std::uint8_t* p, const T& v) {
  std::memcpy(p, &v, sizeof(T));
}
template <class T>
inline void get(const std::uint8_t* p, T& v) {
  std::memcpy(&v, p, sizeof(T));
}
template <class T, std::size_t N>
inline void put_array(std::uint8_t* p, const std::array<T, N>& a) {
  std::memcpy(p, a.data(), sizeof(T) * N);
}
template <class T, std::size_t N>
inline void get_array(const std::uint8_t* p, std::array<T, N>& a) {
  std::memcpy(a.data(), p, sizeof(T) * N);
}
}  // namespace detail

/// Copies a fixed-size MAVLink char array (not necessarily NUL-terminated) into a string.
template <std::size_t N>
std::string to_string(const std::array<char, N>& a) {
  std::size_t n = 0;
  while (n < N && a[n] != '\0') ++n;
  return std::string(a.data(), n);
}
/// Fills a MAVLink char array from s (truncated to N; NUL-padded, no terminator when s fills it).
template <std::size_t N>
std::array<char, N> to_chars(std::string_view s) {
  std::array<char, N> a{};
  for (std::size_t i = 0; i < N && i < s.size(); ++i) a[i] = s[i];
  return a;
}

}  // namespace tern::mavlink
