// frame.cpp: MAVLink 1 and 2 frames and their X.25 checksum (tern/mavlink/frame.hpp).
#include "tern/mavlink/frame.hpp"

namespace tern::mavlink {

std::uint16_t crc_accumulate(std::uint8_t b, std::uint16_t crc) {
  // CRC-16/MCRF4XX, polynomial 0x1021 reflected, as https://mavlink.io/en/guide/crc.html gives it
  std::uint8_t t = static_cast<std::uint8_t>(b ^ static_cast<std::uint8_t>(crc & 0xFF));
  t = static_cast<std::uint8_t>(t ^ static_cast<std::uint8_t>(t << 4));
  return static_cast<std::uint16_t>((crc >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4));
}

std::uint16_t crc_calculate(const std::uint8_t* p, std::size_t n, std::uint16_t crc) {
  for (std::size_t i = 0; i < n; ++i) crc = crc_accumulate(p[i], crc);
  return crc;
}

namespace {
std::uint16_t frame_crc(const std::uint8_t* frame, std::size_t n, std::uint8_t crc_extra) {
  return crc_accumulate(crc_extra, crc_calculate(frame + 1, n - 1));
}
void put_crc(std::uint8_t* at, std::uint16_t crc) {
  at[0] = static_cast<std::uint8_t>(crc & 0xFF);
  at[1] = static_cast<std::uint8_t>(crc >> 8);
}
}  // namespace

bool checksum_matches(const std::uint8_t* frame, std::size_t n, std::uint8_t crc_extra) {
  const std::uint16_t got = static_cast<std::uint16_t>(frame[n] | (frame[n + 1] << 8));
  return frame_crc(frame, n, crc_extra) == got;
}

std::size_t finish_frame_v1(std::uint8_t* out, std::uint8_t len, std::uint8_t seq, std::uint8_t sysid, std::uint8_t compid,
                            std::uint8_t msgid, std::uint8_t crc_extra) {
  out[0] = kStxV1;
  out[1] = len;
  out[2] = seq;
  out[3] = sysid;
  out[4] = compid;
  out[5] = msgid;
  const std::size_t n = kHeaderLengthV1 + len;
  put_crc(out + n, frame_crc(out, n, crc_extra));
  return n + kChecksumLength;
}

std::size_t trimmed_length(const std::uint8_t* payload, std::size_t n) {
  while (n > 1 && payload[n - 1] == 0) --n;
  return n == 0 ? 1 : n;
}

std::size_t finish_frame_v2(std::uint8_t* out, std::size_t n, std::uint8_t seq, std::uint8_t sysid, std::uint8_t compid,
                            std::uint32_t msgid, std::uint8_t crc_extra) {
  if (n == 0) out[kHeaderLengthV2] = 0;  // one byte always goes
  const std::size_t len = trimmed_length(out + kHeaderLengthV2, n < kMaxPayloadLength ? n : kMaxPayloadLength);
  out[0] = kStxV2;
  out[1] = static_cast<std::uint8_t>(len);
  out[2] = 0;  // incompat_flags: unsigned
  out[3] = 0;  // compat_flags
  out[4] = seq;
  out[5] = sysid;
  out[6] = compid;
  out[7] = static_cast<std::uint8_t>(msgid & 0xFF);
  out[8] = static_cast<std::uint8_t>((msgid >> 8) & 0xFF);
  out[9] = static_cast<std::uint8_t>((msgid >> 16) & 0xFF);
  const std::size_t total = kHeaderLengthV2 + len;
  put_crc(out + total, frame_crc(out, total, crc_extra));
  return total + kChecksumLength;
}

std::size_t HeaderV2::frame_length() const {
  return kHeaderLengthV2 + len + kChecksumLength + ((incompat_flags & kIncompatSigned) != 0 ? kSignatureLength : 0);
}

HeaderV2 read_header_v2(const std::uint8_t* h) {
  HeaderV2 r;
  r.len = h[1];
  r.incompat_flags = h[2];
  r.compat_flags = h[3];
  r.seq = h[4];
  r.sysid = h[5];
  r.compid = h[6];
  r.msgid = static_cast<std::uint32_t>(h[7]) | (static_cast<std::uint32_t>(h[8]) << 8) | (static_cast<std::uint32_t>(h[9]) << 16);
  return r;
}

}  // namespace tern::mavlink
