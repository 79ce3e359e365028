// tern/mavlink/frame.hpp: MAVLink framing, versions 1 and 2, and its checksum: the one
// implementation fcu_serial (MAVLink 1 to a ROSflight FCU) and the ground-station endpoint
// (core/apps/mavlink, MAVLink 2 over UDP) share.
//
// MAVLink 1 frame: 0xFE, payload length, sequence, system id, component id, message id, payload,
// checksum. MAVLink 2 frame (https://mavlink.io/en/guide/serialization.html#mavlink2_packet_format):
// 0xFD, payload length, incompat_flags, compat_flags, sequence, system id, component id, message id
// (3 bytes, little-endian), payload, checksum, [signature: 13 bytes when incompat_flags has
// MAVLINK_IFLAG_SIGNED]. MAVLink 2 payloads are sent with their trailing zero bytes trimmed (one byte
// always kept) and read back zero-filled ("payload truncation", same page).
// The checksum is the X.25 CRC (CRC-16/MCRF4XX, https://mavlink.io/en/guide/crc.html, seeded with
// 0xFFFF) over the bytes after the start byte through the payload, then the message's CRC_EXTRA
// byte; sent low byte first.
//
// Errors: none thrown; nothing allocates. Plain C++, no tern host types.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tern::mavlink {

inline constexpr std::uint8_t kStxV1 = 0xFE;           ///< MAVLink 1 start byte
inline constexpr std::size_t kHeaderLengthV1 = 6;      ///< STX len seq sys comp msgid
inline constexpr std::uint8_t kStxV2 = 0xFD;           ///< MAVLink 2 start byte
inline constexpr std::size_t kHeaderLengthV2 = 10;     ///< STX len incompat compat seq sys comp msgid[3]
inline constexpr std::uint8_t kIncompatSigned = 0x01;  ///< MAVLINK_IFLAG_SIGNED
inline constexpr std::size_t kSignatureLength = 13;    ///< link id, 6-byte timestamp, 6-byte signature
inline constexpr std::size_t kChecksumLength = 2;      ///< bytes
inline constexpr std::size_t kMaxPayloadLength = 255;  ///< bytes
inline constexpr std::uint16_t kCrcInit = 0xFFFF;      ///< X.25 start value

/// X.25 CRC accumulation of one byte (MAVLink's crc_accumulate).
std::uint16_t crc_accumulate(std::uint8_t b, std::uint16_t crc);
/// CRC of n bytes starting from `crc`.
std::uint16_t crc_calculate(const std::uint8_t* p, std::size_t n, std::uint16_t crc = kCrcInit);
/// Whether the two bytes after frame[0, n) hold the checksum of frame[1, n) and crc_extra (n: the
/// header and payload, start byte included; either version).
bool checksum_matches(const std::uint8_t* frame, std::size_t n, std::uint8_t crc_extra);

/// Completes a MAVLink 1 frame whose payload (len bytes) is already at out + kHeaderLengthV1:
/// writes the header before it and the checksum after it; returns the frame length.
std::size_t finish_frame_v1(std::uint8_t* out, std::uint8_t len, std::uint8_t seq, std::uint8_t sysid, std::uint8_t compid,
                            std::uint8_t msgid, std::uint8_t crc_extra);

/// The payload length a MAVLink 2 frame sends of n bytes: trailing zeros trimmed, at least one byte.
std::size_t trimmed_length(const std::uint8_t* payload, std::size_t n);
/// Completes a MAVLink 2 frame whose full payload (n <= 255 bytes, at least 1 byte of room) is
/// already at out + kHeaderLengthV2: trims it, writes the header before it (unsigned, no flags) and
/// the checksum after it; returns the frame length.
std::size_t finish_frame_v2(std::uint8_t* out, std::size_t n, std::uint8_t seq, std::uint8_t sysid, std::uint8_t compid,
                            std::uint32_t msgid, std::uint8_t crc_extra);

/// The fields of a MAVLink 2 header at h (kHeaderLengthV2 bytes, start byte first).
struct HeaderV2 {
  std::uint8_t len = 0, incompat_flags = 0, compat_flags = 0, seq = 0, sysid = 0, compid = 0;
  std::uint32_t msgid = 0;  ///< 24 bits
  /// The whole frame: header, payload, checksum and, when signed, the signature.
  std::size_t frame_length() const;
};
HeaderV2 read_header_v2(const std::uint8_t* h);

}  // namespace tern::mavlink
