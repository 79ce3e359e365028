// core/apps/import/text_table.hpp: reads another project's text table one row at a time, for the
// importers: whitespace-separated numbers (InertialNav's .txt) or comma-separated values with a
// header line (rostopic echo -p CSV, as the ALFA dataset ships). Every error is an ImportError
// of one line naming the file, the line and the column: "IMU.txt:120: column 3: 'x' is not a
// number", "GPS.txt:7: expected 14 values, got 9 (a truncated file?)".
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "import/sensor_log_writer.hpp"

namespace tern::core {

class TextTable {
 public:
  enum class Separator { whitespace, comma };
  /// Opens `file`; a comma table reads its header line. Throws ImportError if the file cannot be
  /// opened or (comma) has no header.
  TextTable(std::filesystem::path file, Separator separator);

  /// The index of the header's column `name` (comma tables). Throws ImportError naming the file
  /// and column if it has none.
  std::size_t column(std::string_view name) const;
  /// Reads the next non-empty row; false at the end of the file. Throws ImportError if the row
  /// has fewer than `min_cells` values (or, for a comma table, not as many as the header).
  bool next(std::size_t min_cells = 0);

  std::size_t cells() const { return cells_.size(); }
  /// Cell i (0-based) as a finite number. Throws ImportError naming file, line and column.
  double number(std::size_t i) const;
  /// Cell i as an integer (ROS stamps in ns). Throws ImportError naming file, line and column.
  std::int64_t integer(std::size_t i) const;
  const std::string& text(std::size_t i) const { return cells_.at(i); }

  std::size_t line() const { return line_; }
  const std::filesystem::path& file() const { return file_; }
  /// Throws ImportError "<file>:<line>: <what>".
  [[noreturn]] void fail(const std::string& what) const;

 private:
  std::string column_name(std::size_t i) const;

  std::filesystem::path file_;
  Separator separator_;
  std::ifstream in_;
  std::vector<std::string> header_;
  std::vector<std::string> cells_;
  std::string row_;
  std::size_t line_ = 0;
};

}  // namespace tern::core
