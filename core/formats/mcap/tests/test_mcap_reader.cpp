// core/formats/mcap/tests/test_mcap_reader.cpp: the MCAP reader on a hostile chunk (issue 78): a
// zstd frame that does not declare its size, in a chunk declaring a gigabyte, is refused without
// the gigabyte being allocated (found by fuzz_mcap_recovery: 1.4 kB took 2 GiB).
#include <doctest/doctest.h>
#include <sys/resource.h>
#include <zstd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "mcap/mcap_format.hpp"
#include "mcap/mcap_reader.hpp"

namespace {

std::string le(std::uint64_t v, int bytes) {
  std::string out;
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  return out;
}

std::string record(std::uint8_t op, const std::string& content) {
  std::string r(1, static_cast<char>(op));
  r += le(content.size(), 8);
  r += content;
  return r;
}

std::string str(const std::string& s) { return le(s.size(), 4) + s; }

/// A zstd frame of `plain` whose header omits the content size (as a streaming compressor writes it).
std::string frame_without_size(const std::string& plain) {
  ZSTD_CCtx* c = ZSTD_createCCtx();
  ZSTD_CCtx_setParameter(c, ZSTD_c_contentSizeFlag, 0);
  std::string out(ZSTD_compressBound(plain.size()), '\0');
  const std::size_t n = ZSTD_compress2(c, out.data(), out.size(), plain.data(), plain.size());
  ZSTD_freeCCtx(c);
  REQUIRE(!ZSTD_isError(n));
  out.resize(n);
  return out;
}

long max_rss_kb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

}  // namespace

TEST_CASE("mcap reader: a chunk declaring 1 GiB whose zstd frame holds 64 bytes is damaged, and costs no gigabyte") {
  const std::uint64_t declared = std::uint64_t{1} << 30;
  const std::string frame = frame_without_size(std::string(64, '\0'));
  const std::string chunk = le(0, 8) + le(0, 8) + le(declared, 8) + le(0, 4) + str("zstd") + le(frame.size(), 8) + frame;
  const std::string magic(tern::core::mcap::kMagic, 8);
  const std::string file = magic + record(0x01, str("") + str("")) + record(0x06, chunk) + record(0x0F, le(0, 4)) +
                           record(0x02, le(0, 8) + le(0, 8) + le(0, 4)) + magic;
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "tern_mcap_reader_unsized_frame.mcap";
  std::ofstream(path, std::ios::binary | std::ios::trunc) << file;
  const long before = max_rss_kb();
  tern::core::McapReader reader(path);
  tern::core::McapRecord r;
  bool chunk_seen = false;
  std::string buffer;
  while (reader.next(r))
    if (r.op == tern::core::mcap::Op::chunk) {
      chunk_seen = true;
      try {
        reader.chunk_messages(r, buffer, [](const tern::core::McapMessage&) {});
        FAIL("the chunk was read");
      } catch (const tern::core::McapError& e) {
        CHECK(std::string(e.what()).find("64 bytes of the 1073741824 declared") != std::string::npos);
      }
    }
  CHECK(chunk_seen);
  CHECK(max_rss_kb() - before < 64 * 1024);  // kB: the buffer grew to what the frame gave (1 MiB), not to the declaration
  std::filesystem::remove(path);
}
