// tern_fcu_serial/wire.hpp: byte-level helpers of the MAVLink 1.0 wire format: little-endian
// field packing and the X.25 (CRC-16/MCRF4XX) checksum that MAVLink seeds with 0xFFFF.
// Plain C++, no tern host types.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace tern::fcu::mavlink {

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

/// X.25 CRC accumulation of one byte (MAVLink's crc_accumulate).
constexpr std::uint16_t crc_accumulate(std::uint8_t b, std::uint16_t crc) {
  std::uint8_t tmp = static_cast<std::uint8_t>(b ^ static_cast<std::uint8_t>(crc & 0xFF));
  tmp = static_cast<std::uint8_t>(tmp ^ static_cast<std::uint8_t>(tmp << 4));
  return static_cast<std::uint16_t>((crc >> 8) ^ (tmp << 8) ^ (tmp << 3) ^ (tmp >> 4));
}

inline constexpr std::uint16_t kCrcInit = 0xFFFF;

/// CRC of n bytes starting from `crc`.
constexpr std::uint16_t crc_calculate(const std::uint8_t* p, std::size_t n, std::uint16_t crc = kCrcInit) {
  for (std::size_t i = 0; i < n; ++i) crc = crc_accumulate(p[i], crc);
  return crc;
}

}  // namespace tern::fcu::mavlink
