// fuzz_dataflash: libFuzzer target for the ArduPilot DataFlash reader (core/apps/import/dataflash_reader.hpp),
// as `tern import dataflash` reads a .bin: the message stream resynchronised on 0xA3 0x95, every FMT
// parsed into a layout, then every field of every message decoded (value, integer, text) and its
// TimeUS. Any bytes: the reader gives values or throws DataflashError (one line), never crashes,
// reads out of bounds, loops or allocates without bound.
#include <cstdint>
#include <string>

#include "fuzz_input.hpp"
#include "import/dataflash_reader.hpp"

using namespace tern::core::dataflash;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = tern::fuzz::as_file(data, size, ".bin");
  try {
    Reader r(file);
    const DataflashStats stats = r.read([](const Message& m) {
      // the layout: fields in order, inside the message's length, each found by its label
      const Format& f = m.format();
      std::size_t end = 0;
      for (const Field& x : f.fields) {
        if (x.offset != end) __builtin_trap();
        end = x.offset + field_size(x.type);
        (void)m.value(x);
        (void)m.integer(x);
        (void)m.text(x);
      }
      if (3 + end != f.length) __builtin_trap();
      (void)m.time_us();
    });
    (void)stats.warnings(file.string());
  } catch (const DataflashError& e) {
    tern::fuzz::note(e);
  }
  return 0;
}
