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
  return 0;
}
