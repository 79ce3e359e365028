// core/formats/mcap/mcap_recover.hpp: `tern export recover`: a flight.mcap cut short (a killed
// process, a full disk: no summary, maybe a partial last record) rewritten as a complete file
// with everything up to its last complete chunk, as `mcap recover` does. The schemas, channels,
// messages (re-chunked with the same chunk size), attachments and metadata are copied in their
// order; a damaged chunk ends the copy there. Recovering a complete tern file with its own chunk
// size gives the same bytes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace tern::core {

namespace fs = std::filesystem;

struct RecoverReport {
  std::uint64_t messages = 0, chunks = 0, attachments = 0;
  std::string stopped;  ///< why the copy stopped ("" for a complete input)
};

/// Reads `in`, writes `out` (chunk size `chunk_bytes`); throws McapError for an input that is
/// not MCAP, or an output that cannot be written (one line naming the file).
RecoverReport recover_mcap(const fs::path& in, const fs::path& out, std::size_t chunk_bytes);

}  // namespace tern::core
