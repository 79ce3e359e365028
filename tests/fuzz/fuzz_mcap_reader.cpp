// fuzz_mcap_reader: libFuzzer target for the MCAP reader (core/formats/mcap/mcap_reader.hpp), as
// `tern export` and the replay of an MCAP-only log read a flight.mcap. Any bytes: every record is
// read and taken apart (schemas, channels, attachments, metadata, chunks and their messages); the
// reader either gives records or throws McapError (one line), never crashes, reads out of bounds
// or allocates what a lying length declares.
#include <cstdint>
#include <string>

#include "fuzz_input.hpp"
#include "mcap/mcap_reader.hpp"

using namespace tern::core;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = tern::fuzz::as_file(data, size, ".mcap");
  try {
    McapReader in(file);
    McapRecord r;
    std::string buffer;
    std::size_t messages = 0;
    while (in.next(r)) {
      switch (r.op) {
        case mcap::Op::schema: in.schema(r); break;
        case mcap::Op::channel: in.channel(r); break;
        case mcap::Op::attachment: in.attachment(r); break;
        case mcap::Op::metadata: in.metadata(r); break;
        case mcap::Op::message: in.message(r.content, r.offset); break;
        case mcap::Op::chunk: in.chunk_messages(r, buffer, [&](const McapMessage& m) { messages += m.data.size() > 0; }); break;
        default: break;
      }
    }
  } catch (const McapError&) {
  }
  return 0;
}
