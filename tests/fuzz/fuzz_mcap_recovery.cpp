// fuzz_mcap_recovery: libFuzzer target for `tern export recover` (core/formats/mcap/mcap_recover.hpp):
// a flight.mcap cut short or damaged, rewritten as a complete file with everything up to the last
// record it can read (schemas, channels, messages re-chunked, attachments, metadata). Any bytes:
// recover_mcap either throws McapError (one line: not MCAP, or the output cannot be written) or
// writes a file that the reader (mcap_reader.hpp) reads to its footer without an error or a
// truncation, holding as many messages and attachments as the report says; and recovering that
// file again with the same chunk size gives the same bytes (a complete tern file is its own
// recovery). Never a crash, an out-of-bounds read or an allocation a lying length declares. The
// input and both outputs are this process's files under TMPDIR.
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>

#include "fuzz_input.hpp"
#include "mcap/mcap_reader.hpp"
#include "mcap/mcap_recover.hpp"

using namespace tern::core;

namespace {

/// bytes per chunk of the outputs: small, so that a seed's messages span several chunks.
constexpr std::size_t kChunkBytes = 512;

const fs::path& output(int k) {
  static const tern::fuzz::Scratch a{fs::temp_directory_path() / ("tern-fuzz-" + std::to_string(::getpid()) + ".recovered.mcap")};
  static const tern::fuzz::Scratch b{fs::temp_directory_path() / ("tern-fuzz-" + std::to_string(::getpid()) + ".recovered2.mcap")};
  return k == 0 ? a.path : b.path;
}

std::string bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The recovered file read whole: complete, and holding what the report counted.
void check_complete(const fs::path& file, const RecoverReport& report) {
  std::uint64_t messages = 0, attachments = 0;
  try {
    McapReader in(file);
    McapRecord r;
    std::string buffer;
    while (in.next(r)) {
      switch (r.op) {
        case mcap::Op::schema: in.schema(r); break;
        case mcap::Op::channel: in.channel(r); break;
        case mcap::Op::metadata: in.metadata(r); break;
        case mcap::Op::attachment:
          in.attachment(r);
          ++attachments;
          break;
        case mcap::Op::message:
          in.message(r.content, r.offset);
          ++messages;
          break;
        case mcap::Op::chunk: in.chunk_messages(r, buffer, [&](const McapMessage&) { ++messages; }); break;
        default: break;
      }
    }
    if (!in.truncated().empty()) __builtin_trap();  // the output is complete
  } catch (const McapError&) {
    __builtin_trap();  // the output reads without an error
  }
  if (messages != report.messages || attachments != report.attachments) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto in = tern::fuzz::as_file(data, size, ".mcap");
  RecoverReport first;
  try {
    first = recover_mcap(in, output(0), kChunkBytes);
  } catch (const McapError& e) {
    tern::fuzz::note(e);
    return 0;
  }
  check_complete(output(0), first);
  // the recovered file is complete: recovering it again changes nothing
  RecoverReport second;
  try {
    second = recover_mcap(output(0), output(1), kChunkBytes);
  } catch (const McapError&) {
    __builtin_trap();
  }
  if (!second.stopped.empty() || second.messages != first.messages || second.attachments != first.attachments) __builtin_trap();
  if (bytes_of(output(0)) != bytes_of(output(1))) __builtin_trap();
  return 0;
}
