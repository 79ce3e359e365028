// fuzz_mavlink: libFuzzer target for the MAVLink parser and decoder (see README.md).
// Any input: the parser must not crash, read out of bounds or loop; every frame it delivers must
// have the dialect's length and decode; re-encoding a decoded message gives back the same payload.
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "tern_fcu_serial/codec.hpp"

using namespace tern::fcu::mavlink;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Parser p;
  std::size_t frames = 0;
  // feed in two pieces to exercise partial frames across calls
  const std::size_t half = size / 2;
  auto on_frame = [&](const Frame& f) {
    ++frames;
    const MessageInfo* info = find_message(f.msgid);
    if (info == nullptr || info->length != f.len) std::abort();
    const auto m = decode(f);
    if (m) {
      std::visit(
          [&](const auto& msg) {
            std::uint8_t out[kMaxFrameLength];
            const std::size_t n = encode(msg, f.seq, f.sysid, f.compid, out);
            if (n != kHeaderLength + f.len + 2) std::abort();
            if (std::memcmp(out + kHeaderLength, f.payload.data(), f.len) != 0) std::abort();
          },
          *m);
    }
  };
  p.feed(data, half, on_frame);
  p.feed(data + half, size - half, on_frame);
  if (p.stats().bytes != size || p.stats().frames != frames) std::abort();

  // Random bytes rarely carry a valid checksum: also wrap them into a well-formed frame of the
  // dialect message named by the first byte (correct length and CRC), between the two halves of
  // the input, so that every decoder is reached. That frame must come out.
  if (size >= 1) {
    const MessageInfo* info = find_message(data[0]);
    if (info != nullptr) {
      std::uint8_t frame[kMaxFrameLength] = {kStx, info->length, 0, 1, 1, info->id};
      for (std::size_t i = 0; i < info->length; ++i) frame[kHeaderLength + i] = 1 + i < size ? data[1 + i] : 0;
      std::uint16_t crc = crc_calculate(frame + 1, kHeaderLength - 1 + info->length);
      crc = crc_accumulate(info->crc_extra, crc);
      frame[kHeaderLength + info->length] = static_cast<std::uint8_t>(crc & 0xFF);
      frame[kHeaderLength + info->length + 1] = static_cast<std::uint8_t>(crc >> 8);
      Parser q;
      bool seen = false;
      auto check = [&](const Frame& f) {
        on_frame(f);
        if (f.msgid == info->id && std::memcmp(f.payload.data(), frame + kHeaderLength, info->length) == 0) seen = true;
      };
      q.feed(data, half, check);
      const auto before = q.stats().frames;
      q.feed(frame, kHeaderLength + info->length + 2u, check);
      // A partial frame left by the first half may swallow the start of ours; it then fails its
      // checksum and ours is rescanned from its start byte. Zeros at the end complete any
      // partial frame. Ours can only be lost to a frame that passed its checksum by chance.
      q.feed(data + half, size - half, check);
      const std::uint8_t zeros[kMaxFrameLength] = {};
      q.feed(zeros, sizeof zeros, check);
      if (!seen && q.stats().frames == before) std::abort();
    }
  }
  return 0;
}
