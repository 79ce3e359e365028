// core/apps/mavlink/mavlink_codec.cpp: MAVLink 2 frames (mavlink_codec.hpp).
#include "mavlink/mavlink_codec.hpp"

namespace tern::core::mavlink {

std::uint16_t crc_accumulate(std::uint8_t b, std::uint16_t crc) {
  // CRC-16/MCRF4XX, polynomial 0x1021 reflected, as https://mavlink.io/en/guide/crc.html gives it
  std::uint8_t t = static_cast<std::uint8_t>(b ^ static_cast<std::uint8_t>(crc & 0xFF));
  t = static_cast<std::uint8_t>(t ^ (t << 4));
  return static_cast<std::uint16_t>((crc >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4));
}

std::uint16_t crc_x25(const std::uint8_t* data, std::size_t n, std::uint16_t crc) {
  for (std::size_t i = 0; i < n; ++i) crc = crc_accumulate(data[i], crc);
  return crc;
}

std::vector<std::uint8_t> encode_frame(std::uint32_t msgid, const std::vector<std::uint8_t>& payload, std::uint8_t seq, std::uint8_t sysid,
                                       std::uint8_t compid) {
  const MessageInfo info = *message_info(msgid);
  std::size_t len = payload.size() < kMaxPayload ? payload.size() : kMaxPayload;
  while (len > 1 && payload[len - 1] == 0) --len;  // zero trimming; one byte always stays
  if (len == 0) len = 1;
  std::vector<std::uint8_t> out;
  out.reserve(kHeaderLen + len + 2);
  out.push_back(kMagicV2);
  out.push_back(static_cast<std::uint8_t>(len));
  out.push_back(0);  // incompat_flags: unsigned
  out.push_back(0);  // compat_flags
  out.push_back(seq);
  out.push_back(sysid);
  out.push_back(compid);
  out.push_back(static_cast<std::uint8_t>(msgid & 0xFF));
  out.push_back(static_cast<std::uint8_t>((msgid >> 8) & 0xFF));
  out.push_back(static_cast<std::uint8_t>((msgid >> 16) & 0xFF));
  for (std::size_t i = 0; i < len; ++i) out.push_back(i < payload.size() ? payload[i] : 0);
  std::uint16_t crc = crc_x25(out.data() + 1, out.size() - 1);
  crc = crc_accumulate(info.crc_extra, crc);
  out.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  out.push_back(static_cast<std::uint8_t>(crc >> 8));
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
      if (i + 1 >= n || i + 8 + data[i + 1] > n) {
        ++c.truncated;
        return frames;
      }
      i += 8 + data[i + 1];
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
    const std::uint8_t len = data[i + 1];
    const bool signed_frame = (data[i + 2] & kIncompatSigned) != 0;
    const std::size_t total = kHeaderLen + len + 2 + (signed_frame ? kSignatureLen : 0);
    if (n - i < total) {
      ++c.truncated;
      return frames;
    }
    const std::uint32_t msgid = static_cast<std::uint32_t>(data[i + 7]) | (static_cast<std::uint32_t>(data[i + 8]) << 8) |
                                (static_cast<std::uint32_t>(data[i + 9]) << 16);
    const auto info = message_info(msgid);
    if (!info) {
      ++c.unknown_id;
      i += total;
      continue;
    }
    std::uint16_t crc = crc_x25(data + i + 1, kHeaderLen - 1 + len);
    crc = crc_accumulate(info->crc_extra, crc);
    const std::uint16_t got = static_cast<std::uint16_t>(data[i + kHeaderLen + len] | (data[i + kHeaderLen + len + 1] << 8));
    if (crc != got) {
      ++c.bad_crc;
      ++i;  // a start byte inside noise: look for the next one
      continue;
    }
    if (len > info->length) {
      ++c.bad_length;
      i += total;
      continue;
    }
    Frame f;
    f.seq = data[i + 4];
    f.sysid = data[i + 5];
    f.compid = data[i + 6];
    f.msgid = msgid;
    f.payload.assign(data + i + kHeaderLen, data + i + kHeaderLen + len);
    f.payload.resize(info->length, 0);  // zero-filled past what was sent
    frames.push_back(std::move(f));
    ++c.frames;
    i += total;
  }
  if (n == 0 || c.junk_bytes - junk_before == n) ++c.noise;  // nothing in it looked like a frame
  return frames;
}

}  // namespace tern::core::mavlink
