#include "import/text_table.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "tern/input_file.hpp"

namespace tern::core {

namespace {

void split(const std::string& row, TextTable::Separator separator, std::vector<std::string>& cells) {
  cells.clear();
  if (separator == TextTable::Separator::comma) {
    std::size_t start = 0;
    for (;;) {
      const std::size_t comma = row.find(',', start);
      cells.push_back(row.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    return;
  }
  std::size_t i = 0;
  while (i < row.size()) {
    while (i < row.size() && std::isspace(static_cast<unsigned char>(row[i]))) ++i;
    const std::size_t start = i;
    while (i < row.size() && !std::isspace(static_cast<unsigned char>(row[i]))) ++i;
    if (i > start) cells.push_back(row.substr(start, i - start));
  }
}

bool blank(const std::string& row) {
  for (char c : row)
    if (!std::isspace(static_cast<unsigned char>(c))) return false;
  return true;
}

}  // namespace

TextTable::TextTable(std::filesystem::path file, Separator separator) : file_(std::move(file)), separator_(separator) {
  if (const std::string p = input_file_problem(file_, kMaxTableBytes); !p.empty() && std::filesystem::exists(file_))
    throw ImportError(fmt::format("{}: the table {}", printable(file_.string()), p));
  in_.open(file_);
  if (!in_) throw ImportError(fmt::format("{}: cannot open it", file_.string()));
  if (separator_ != Separator::comma) return;
  if (!std::getline(in_, row_)) throw ImportError(fmt::format("{}: empty (a CSV header line was expected)", file_.string()));
  line_ = 1;
  if (!row_.empty() && row_.back() == '\r') row_.pop_back();
  split(row_, separator_, header_);
}

std::size_t TextTable::column(std::string_view name) const {
  for (std::size_t i = 0; i < header_.size(); ++i)
    if (header_[i] == name) return i;
  throw ImportError(fmt::format("{}:1: no column '{}'", file_.string(), name));
}

bool TextTable::next(std::size_t min_cells) {
  while (std::getline(in_, row_)) {
    ++line_;
    if (!row_.empty() && row_.back() == '\r') row_.pop_back();
    if (blank(row_)) continue;
    split(row_, separator_, cells_);
    const std::size_t expected = separator_ == Separator::comma ? header_.size() : min_cells;
    if (cells_.size() < expected || cells_.size() < min_cells)
      fail(fmt::format("expected {} values, got {} (a truncated file?)", std::max(expected, min_cells), cells_.size()));
    return true;
  }
  return false;
}

std::string TextTable::column_name(std::size_t i) const {
  if (i < header_.size()) return fmt::format("column '{}'", header_[i]);
  return fmt::format("column {}", i + 1);
}

double TextTable::number(std::size_t i) const {
  const std::string& s = cells_.at(i);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v))
    fail(fmt::format("{}: '{}' is not a finite number", column_name(i), s));
  return v;
}

std::int64_t TextTable::integer(std::size_t i) const {
  const std::string& s = cells_.at(i);
  std::int64_t v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || p != s.data() + s.size()) fail(fmt::format("{}: '{}' is not an integer", column_name(i), s));
  return v;
}

void TextTable::fail(const std::string& what) const { throw ImportError(fmt::format("{}:{}: {}", file_.string(), line_, what)); }

}  // namespace tern::core
