// core/apps/mavlink/mavlink_codec.cpp: MAVLink 2 frames in UDP datagrams (mavlink_codec.hpp).
#include "mavlink/mavlink_codec.hpp"

#include <algorithm>

namespace tern::core::mavlink {

std::optional<MessageInfo> message_info(std::uint32_t msgid) {
  for (const MessageInfo& m : kDialect)
    if (m.id == msgid) return m;
  return std::nullopt;
}

std::optional<std::uint8_t> target_system(const Frame& f) {
  const auto info = message_info(f.msgid);
  if (!info || info->target_system_offset < 0) return std::nullopt;
  const auto at = static_cast<std::size_t>(info->target_system_offset);
  return at < f.payload.size() ? f.payload[at] : std::uint8_t{0};  // an extension not sent reads 0
}

std::vector<std::uint8_t> encode_frame(std::uint32_t msgid, const std::vector<std::uint8_t>& payload, std::uint8_t seq, std::uint8_t sysid,
                                       std::uint8_t compid) {
  const MessageInfo info = *message_info(msgid);
  std::vector<std::uint8_t> out(kHeaderLen + std::max<std::size_t>(payload.size(), 1) + ::tern::mavlink::kChecksumLength, 0);
  std::copy(payload.begin(), payload.end(), out.begin() + kHeaderLen);
  out.resize(::tern::mavlink::finish_frame_v2(out.data(), payload.size(), seq, sysid, compid, msgid, info.crc_extra));
  return out;
}

std::vector<Frame> parse_datagram(const std::uint8_t* data, std::size_t n, Counters& c) {
  ++c.datagrams;
  std::vector<Frame> frames;
  const std::uint64_t junk_before = c.junk_bytes;
  std::size_t i = 0;
  while (i < n) {
    if (data[i] == kMagicV1) {  // a MAVLink 1 frame: len at [1], 6 header bytes, 2 checksum bytes
      ++c.mavlink1;
      constexpr std::size_t v1_overhead = ::tern::mavlink::kHeaderLengthV1 + ::tern::mavlink::kChecksumLength;
      if (i + 1 >= n || i + v1_overhead + data[i + 1] > n) {
        ++c.truncated;
        return frames;
      }
      i += v1_overhead + data[i + 1];
      continue;
    }
    if (data[i] != kMagicV2) {
      ++c.junk_bytes;
      ++i;
      continue;
    }
    if (n - i < kHeaderLen + 2) {
      ++c.truncated;
      return frames;
    }
    const ::tern::mavlink::HeaderV2 h = ::tern::mavlink::read_header_v2(data + i);
    const std::size_t total = h.frame_length();
    if (n - i < total) {
      ++c.truncated;
      return frames;
    }
    const auto info = message_info(h.msgid);
    if (!info) {
      ++c.unknown_id;
      i += total;
      continue;
    }
    if (!::tern::mavlink::checksum_matches(data + i, kHeaderLen + h.len, info->crc_extra)) {
      ++c.bad_crc;
      ++i;  // a start byte inside noise: look for the next one
      continue;
    }
    if (h.len > info->length) {
      ++c.bad_length;
      i += total;
      continue;
    }
    Frame f;
    f.seq = h.seq;
    f.sysid = h.sysid;
    f.compid = h.compid;
    f.msgid = h.msgid;
    f.payload.assign(data + i + kHeaderLen, data + i + kHeaderLen + h.len);
    f.payload.resize(info->length, 0);  // zero-filled past what was sent
    frames.push_back(std::move(f));
    ++c.frames;
    i += total;
  }
  if (n == 0 || c.junk_bytes - junk_before == n) ++c.noise;  // nothing in it looked like a frame
  return frames;
}

}  // namespace tern::core::mavlink
