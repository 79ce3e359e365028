// core/apps/mavlink/mavlink_codec.hpp: MAVLink 2 framing (tern's own codec, no generated headers).
//
// A frame (https://mavlink.io/en/guide/serialization.html#mavlink2_packet_format):
//   0xFD, len, incompat_flags, compat_flags, seq, sysid, compid, msgid (3 bytes, little endian),
//   payload (len bytes), checksum (2 bytes, little endian), [signature: 13 bytes when
//   incompat_flags has MAVLINK_IFLAG_SIGNED (0x01)].
// The checksum is the X.25 CRC (CRC-16/MCRF4XX, https://mavlink.io/en/guide/crc.html) over the
// bytes after the magic through the payload, then the message's CRC_EXTRA byte (computed from its
// XML definition: tests/mavlink/crc_extra_from_xml.py). Payloads are sent with their trailing zero
// bytes trimmed (at least one byte kept) and read back zero-filled to the message's full length
// ("Payload truncation", same page).
//
// Errors: nothing throws. Bytes that are not a frame are counted by FrameParser (Counters) and
// dropped; a frame whose id tern does not know cannot have its checksum checked and is counted as
// unknown. Signed frames are accepted without verifying the signature (tern has no signing keys).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace tern::core::mavlink {

inline constexpr std::uint8_t kMagicV2 = 0xFD;         ///< MAVLink 2 start-of-frame
inline constexpr std::uint8_t kMagicV1 = 0xFE;         ///< MAVLink 1 start-of-frame (not spoken: counted, dropped)
inline constexpr std::size_t kHeaderLen = 10;          ///< magic through msgid
inline constexpr std::size_t kMaxPayload = 255;        ///< bytes
inline constexpr std::uint8_t kIncompatSigned = 0x01;  ///< MAVLINK_IFLAG_SIGNED
inline constexpr std::size_t kSignatureLen = 13;       ///< link id, 6-byte timestamp, 6-byte signature

/// X.25 CRC accumulation of one byte (MAVLink's crc_accumulate), start value 0xFFFF.
std::uint16_t crc_accumulate(std::uint8_t b, std::uint16_t crc);
/// X.25 CRC of `n` bytes from `crc` (0xFFFF for a fresh one).
std::uint16_t crc_x25(const std::uint8_t* data, std::size_t n, std::uint16_t crc = 0xFFFF);

/// A message as read from or written to a frame: ids and the payload (full length after a read,
/// zero-filled past what was sent).
struct Frame {
  std::uint8_t seq = 0;
  std::uint8_t sysid = 0, compid = 0;
  std::uint32_t msgid = 0;  ///< 24 bits
  std::vector<std::uint8_t> payload;
};

/// The CRC_EXTRA and the full (base + extension) payload length of a message id tern knows;
/// nullopt for others (mavlink_messages.cpp holds the table).
struct MessageInfo {
  std::uint8_t crc_extra;
  std::uint8_t length;  ///< bytes, base fields plus extensions
};
std::optional<MessageInfo> message_info(std::uint32_t msgid);

/// Serialises `payload` (the full length; trailing zeros are trimmed here) as a MAVLink 2 frame of
/// message `msgid` from `sysid`/`compid` with sequence number `seq`. `msgid` must be a known id.
std::vector<std::uint8_t> encode_frame(std::uint32_t msgid, const std::vector<std::uint8_t>& payload, std::uint8_t seq, std::uint8_t sysid,
                                       std::uint8_t compid);

/// What was received and dropped, for SYS_STATUS (drop_rate_comm, errors_comm) and the end-of-run
/// line. Counts since construction.
struct Counters {
  std::uint64_t datagrams = 0;   ///< UDP datagrams read
  std::uint64_t frames = 0;      ///< frames with a good checksum of a known message
  std::uint64_t bad_crc = 0;     ///< frames of a known id whose checksum failed
  std::uint64_t truncated = 0;   ///< a frame cut short by the datagram's end
  std::uint64_t unknown_id = 0;  ///< well-formed frames of a message tern does not know
  std::uint64_t mavlink1 = 0;    ///< MAVLink 1 frames (0xFE): not spoken
  std::uint64_t junk_bytes = 0;  ///< bytes skipped looking for a start-of-frame
  std::uint64_t bad_length = 0;  ///< a known message longer than its definition
  std::uint64_t noise = 0;       ///< datagrams without a start-of-frame byte at all
  std::uint64_t dropped() const { return bad_crc + truncated + unknown_id + mavlink1 + bad_length + noise; }
};

/// Reads the frames of one UDP datagram (a datagram holds whole frames; nothing is carried over to
/// the next one). Returns the good frames in order; counts the rest in `c`.
std::vector<Frame> parse_datagram(const std::uint8_t* data, std::size_t n, Counters& c);

}  // namespace tern::core::mavlink
