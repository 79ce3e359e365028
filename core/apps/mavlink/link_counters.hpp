// core/apps/mavlink/link_counters.hpp: what the ground-station endpoint received and dropped
// (parse_datagram counts it, mavlink_codec.hpp), for SYS_STATUS and the end-of-run line; a plain
// struct, so that the host's command line reads it without the MAVLink headers.
#pragma once

#include <cstdint>

namespace tern::core::mavlink {

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
  /// Good frames addressed to a system no vehicle on the endpoint has (ignored, as MAVLink's
  /// routing has it; not errors: not in dropped()).
  std::uint64_t other_system = 0;
  std::uint64_t dropped() const { return bad_crc + truncated + unknown_id + mavlink1 + bad_length + noise; }
};

}  // namespace tern::core::mavlink
