// core/apps/export/mcap_csv_export.hpp: `tern export csv`: a flight's flight.mcap back into the
// topic tables the CSV log writes (topics/<topic>.csv: same names, header, column order and
// number formatting, csv_rows.hpp), so that spreadsheets and `tern plot` read an MCAP-only flight.
//
// Each channel "/<topic>" written by tern carries its CSV header in its metadata
// (tern.csv_header) and a tern_msgs ros2msg schema of one primitive field per column
// (cdr_columns.hpp); the messages are decoded with the schema's field types and formatted by the
// log's own code, so the tables are the CSV log's byte for byte. Channels of other writers
// (no tern.csv_header) are skipped and named in the report.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace tern::core {

namespace fs = std::filesystem;

struct CsvExportReport {
  std::map<std::string, std::uint64_t> rows;  ///< topic -> rows written
  std::vector<std::string> skipped;           ///< channels that are not tern topic tables
  std::string stopped;                        ///< "" for a complete file, else where it was cut
};

/// Reads `mcap_file`, writes `out_dir`/<topic>.csv (created; an existing table is an error:
/// nothing is overwritten), for the topics in `only` (empty: every topic). Throws McapError with
/// one line naming the file and the field.
CsvExportReport export_csv(const fs::path& mcap_file, const fs::path& out_dir, const std::set<std::string>& only = {});

}  // namespace tern::core
