#include "replay/replay_csv.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>

#include <fmt/format.h>

#include "config/error.hpp"
#include "replay/table_limits.hpp"
#include "tern/input_file.hpp"

namespace tern::core {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The cells of one CSV line, split at commas (no quoting: topic tables have none).
void split(std::string_view line, std::vector<std::string_view>& cells) {
  cells.clear();
  for (std::size_t start = 0;;) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    if (comma == std::string_view::npos) return;
    start = comma + 1;
  }
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

/// A cell as a number: NaN for `nan`/`-nan`/empty (is_nan set), nullopt if not a number.
std::optional<double> parse_cell(std::string_view cell, bool& is_nan) {
  cell = trim(cell);
  is_nan = false;
  if (cell.empty()) {
    is_nan = true;
    return kNaN;
  }
  if (cell.front() == '+') cell.remove_prefix(1);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  if (ec != std::errc() || end != cell.data() + cell.size()) return std::nullopt;
  is_nan = !std::isfinite(v);
  return v;
}

std::string field_name(std::string_view header_cell) {
  header_cell = trim(header_cell);
  return std::string(trim(header_cell.substr(0, header_cell.find('['))));
}

}  // namespace

const std::vector<double>& CsvTable::at(const std::string& name) const {
  const auto it = columns.find(name);
  if (it == columns.end()) throw ConfigError(fmt::format("{}: no column '{}'", file.string(), name));
  return it->second;
}

void drop_byte_order_mark(std::string& header) {
  if (header.rfind("\xEF\xBB\xBF", 0) == 0) header.erase(0, 3);
}

void require_comma_separated(const std::filesystem::path& file, const std::string& header) {
  if (header.find(',') != std::string::npos) return;
  const char* by = header.find(';') != std::string::npos ? "';'" : header.find('\t') != std::string::npos ? "tabs" : nullptr;
  if (!by) return;  // one column, or none: the columns' own checks name what is missing
  throw ConfigError(
      fmt::format("{}:1: the header's cells are separated by {}: the tables are comma-separated, with a point for "
                  "the decimals (docs/sensor-log.md); a spreadsheet in a locale with decimal commas exports semicolons",
                  file.string(), by));
}

CsvTable read_csv_table(const std::filesystem::path& file, const std::vector<std::string>& wanted) {
  check_table_file(file);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("{}: cannot open", file.string()));
  CsvTable table;
  table.file = file;
  std::string line;
  std::getline(in, line);
  drop_byte_order_mark(line);
  require_comma_separated(file, line);
  std::vector<std::string_view> cells;
  split(line, cells);
  std::vector<std::vector<double>*> target(cells.size(), nullptr);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::string name = field_name(cells[i]);
    if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), name) == wanted.end()) continue;
    if (table.columns.count(name) != 0)  // two cells would fill one column: which is the field?
      throw ConfigError(fmt::format("{}:1: column '{}' twice in the header", file.string(), printable(name)));
    target[i] = &table.columns[name];
  }
  const std::size_t width = cells.size();
  for (std::size_t lineno = 2; std::getline(in, line); ++lineno) {
    if (in.eof()) {  // no line end: the run was cut off while writing this row
      if (!trim(line).empty())
        table.partial_last_line =
            fmt::format("{}:{}: the last line has no line end (cut off while writing): dropped", file.string(), lineno);
      break;
    }
    if (trim(line).empty()) continue;
    split(line, cells);
    if (cells.size() != width)
      throw ConfigError(fmt::format("{}:{}: {} values, the header has {} columns", file.string(), lineno, cells.size(), width));
    bool row_nan = false;
    for (std::size_t i = 0; i < width; ++i) {
      bool is_nan = false;
      const auto v = parse_cell(cells[i], is_nan);
      if (!v)
        throw ConfigError(fmt::format("{}:{}: column {}: '{}' is not a number", file.string(), lineno, i + 1, std::string(trim(cells[i]))));
      table.nan_cells += is_nan ? 1 : 0;
      row_nan = row_nan || is_nan;
      if (target[i] != nullptr) target[i]->push_back(*v);
    }
    table.nan_rows += row_nan ? 1 : 0;
    ++table.rows;
  }
  return table;
}

namespace {

/// The fields of one params.csv line: commas outside double quotes separate, "" is a quote.
std::vector<std::string> split_quoted(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '"' && quoted && i + 1 < line.size() && line[i + 1] == '"') {
      out.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      out.emplace_back();
    } else if (c != '\r') {
      out.back() += c;
    }
  }
  return out;
}

}  // namespace

ParamHistory read_params_csv(const std::filesystem::path& file) {
  check_table_file(file);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("{}: cannot open", file.string()));
  ParamHistory h;
  std::string line;
  std::getline(in, line);  // header
  for (std::size_t lineno = 2; std::getline(in, line); ++lineno) {
    if (trim(line).empty()) continue;
    const auto f = split_quoted(line);
    bool is_nan = false;
    const auto t = f.empty() ? std::nullopt : parse_cell(f[0], is_nan);
    if (f.size() < 3 || !t) throw ConfigError(fmt::format("{}:{}: expected 't [s],parameter,value,source'", file.string(), lineno));
    h.values[f[1]].emplace_back(*t, f[2]);
  }
  return h;
}

std::optional<double> ParamHistory::number_at(const std::string& name, double t_s) const {
  const auto it = values.find(name);
  if (it == values.end() || it->second.empty()) return std::nullopt;
  const std::string* text = &it->second.front().second;
  for (const auto& [t, v] : it->second)
    if (t <= t_s) text = &v;
  bool is_nan = false;
  const auto v = parse_cell(*text, is_nan);
  if (!v || is_nan) return std::nullopt;
  return v;
}

}  // namespace tern::core
