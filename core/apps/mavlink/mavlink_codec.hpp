// core/apps/mavlink/mavlink_codec.hpp: the endpoint's MAVLink 2 frames over UDP datagrams, on the
// SDK's framing and checksum (tern/mavlink/frame.hpp: the frame layout, payload truncation, the
// X.25 checksum) and the common.xml messages generated at build time (mavlink/common_messages.hpp,
// by sdk/mavlink/generate.py; core/apps/CMakeLists.txt names the messages).
//
// Payloads are sent with their trailing zero bytes trimmed (at least one byte kept) and read back
// zero-filled to the message's full length, so that T::unpack reads a Frame's payload whole.
//
// Errors: nothing throws. Bytes that are not a frame are counted by parse_datagram (Counters) and
// dropped; a frame whose id tern does not know cannot have its checksum checked and is counted as
// unknown. Signed frames are accepted without verifying the signature (tern has no signing keys).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "mavlink/common_messages.hpp"
#include "mavlink/link_counters.hpp"
#include "tern/mavlink/frame.hpp"

namespace tern::core::mavlink {

using ::tern::mavlink::crc_accumulate;
using ::tern::mavlink::crc_calculate;
using ::tern::mavlink::to_chars;
using ::tern::mavlink::to_string;
inline constexpr std::uint8_t kMagicV2 = ::tern::mavlink::kStxV2;            ///< MAVLink 2 start-of-frame
inline constexpr std::uint8_t kMagicV1 = ::tern::mavlink::kStxV1;            ///< MAVLink 1 start-of-frame (not spoken: counted, dropped)
inline constexpr std::size_t kHeaderLen = ::tern::mavlink::kHeaderLengthV2;  ///< magic through msgid

/// A message as read from or written to a frame: ids and the payload (full length after a read,
/// zero-filled past what was sent).
struct Frame {
  std::uint8_t seq = 0;
  std::uint8_t sysid = 0, compid = 0;
  std::uint32_t msgid = 0;  ///< 24 bits
  std::vector<std::uint8_t> payload;
};

/// The table row (CRC_EXTRA, full payload length) of a message id tern knows; nullopt for others.
std::optional<MessageInfo> message_info(std::uint32_t msgid);

/// The system a frame is addressed to: its message's target_system field (0: every system, as
/// MAVLink's routing has it), or nullopt for a message without one (HEARTBEAT, PARAM_VALUE: every
/// system's too). `f` as parse_datagram delivers it (a known id, the payload full length).
std::optional<std::uint8_t> target_system(const Frame& f);

/// Serialises `payload` (the full length; trailing zeros are trimmed here) as a MAVLink 2 frame of
/// message `msgid` from `sysid`/`compid` with sequence number `seq`. `msgid` must be a known id.
std::vector<std::uint8_t> encode_frame(std::uint32_t msgid, const std::vector<std::uint8_t>& payload, std::uint8_t seq, std::uint8_t sysid,
                                       std::uint8_t compid);

/// The full-length payload of a generated message struct (common_messages.hpp).
template <class T>
std::vector<std::uint8_t> encode(const T& m) {
  std::vector<std::uint8_t> p(T::kLength, 0);
  m.pack(p.data());
  return p;
}
/// The message in a frame that parse_datagram delivered (its payload zero-filled to full length)
/// with id T::kId.
template <class T>
T decode(const Frame& f) {
  return T::unpack(f.payload.data());
}

/// Reads the frames of one UDP datagram (a datagram holds whole frames; nothing is carried over to
/// the next one). Returns the good frames in order; counts the rest in `c`.
std::vector<Frame> parse_datagram(const std::uint8_t* data, std::size_t n, Counters& c);

}  // namespace tern::core::mavlink
