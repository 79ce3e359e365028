// core/apps/replay/replay_csv.hpp: the numeric tables of a run directory as the replay report reads
// them: a topic CSV (topics/<name>.csv: header `name [unit]`, one row per sample, numbers) and
// params.csv (`t [s],parameter,value,source`, values possibly quoted).
//
// Errors: ConfigError, one line "file:line: what" for a short or long row or a cell that is not a
// number. Cells `nan`, `-nan`, `inf` and empty cells read as NaN (a reference topic leaves a
// field it lacks empty, docs/sensor-log.md) and are counted. A last line without a line end (a
// run cut off while writing) is dropped and named in `partial_last_line`.
#pragma once

#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace tern::core {

/// Columns of one topic CSV, by field name (the header's name without its " [unit]").
struct CsvTable {
  std::filesystem::path file;
  std::map<std::string, std::vector<double>> columns;  ///< only the columns asked for (those present)
  std::size_t rows = 0;
  std::size_t nan_cells = 0;      ///< NaN or empty cells in any column (asked for or not)
  std::size_t nan_rows = 0;       ///< rows with at least one such cell
  std::string partial_last_line;  ///< "" or why the last line was dropped

  bool has(const std::string& name) const { return columns.count(name) != 0; }
  /// The column; throws ConfigError "file: no column 'name'" when absent.
  const std::vector<double>& at(const std::string& name) const;
};

/// A table's header line without the UTF-8 byte order mark that Excel's "CSV UTF-8", pandas'
/// encoding="utf-8-sig" and PowerShell write before it (the first column would read "\xEF\xBB\xBFt").
void drop_byte_order_mark(std::string& header);

/// Throws ConfigError "<file>:1: the header's cells are separated by ';' ..." when `header` has no
/// comma but a semicolon or a tab: a spreadsheet's "CSV" in a locale with decimal commas (or a
/// tab-separated export) was refused on its second line, its whole row shown as one cell.
void require_comma_separated(const std::filesystem::path& file, const std::string& header);

/// Reads `file`, keeping the columns named in `wanted` (all when empty). Throws ConfigError.
CsvTable read_csv_table(const std::filesystem::path& file, const std::vector<std::string>& wanted = {});

/// params.csv: every value each parameter took, with the flight time it took it (s).
struct ParamHistory {
  /// "instance.name" -> [(t_s, text)] in file order.
  std::map<std::string, std::vector<std::pair<double, std::string>>> values;
  /// The value in effect at time t (the last row at or before t, else the first), as a number;
  /// nullopt when the parameter is absent or its value is not a number.
  std::optional<double> number_at(const std::string& name, double t_s) const;
};

/// Reads params.csv. Throws ConfigError "file:line: ..." for a row without three fields.
ParamHistory read_params_csv(const std::filesystem::path& file);

}  // namespace tern::core
