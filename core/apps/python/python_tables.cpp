#include "python/python_tables.hpp"

#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "config/error.hpp"

namespace tern::core::python {

namespace {

enum class Kind : char { f64, i64, boolean };

struct Column {
  std::string name;
  Kind kind;
  std::size_t offset;
};

/// The columns of a structured dtype (field order = the header's column order).
std::vector<Column> columns_of(const py::dtype& dtype, const std::string& path) {
  std::vector<Column> out;
  const py::tuple names = dtype.attr("names");
  const py::dict fields = dtype.attr("fields");
  for (const auto& n : names) {
    const py::tuple f = fields[n];
    const py::dtype t = f[0].cast<py::dtype>();
    const char k = t.kind();
    Kind kind;
    if (k == 'f' && t.itemsize() == 8)
      kind = Kind::f64;
    else if (k == 'i' && t.itemsize() == 8)
      kind = Kind::i64;
    else if (k == 'b')
      kind = Kind::boolean;
    else
      throw ConfigError(fmt::format("{}: column '{}': dtype {} is not float64, int64 or bool", path, n.cast<std::string>(),
                                    py::repr(t).cast<std::string>()));
    out.push_back({n.cast<std::string>(), kind, f[1].cast<std::size_t>()});
  }
  return out;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw ConfigError(fmt::format("{}: cannot open", path));
  std::string text(static_cast<std::size_t>(in.tellg()), '\0');
  in.seekg(0);
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  return text;
}

/// Where each row starts in `text` (after the header), plus the end.
std::vector<std::size_t> row_starts(const std::string& text) {
  std::vector<std::size_t> starts;
  std::size_t p = text.find('\n');
  p = p == std::string::npos ? text.size() : p + 1;
  while (p < text.size()) {
    starts.push_back(p);
    const void* nl = std::memchr(text.data() + p, '\n', text.size() - p);
    p = nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - text.data()) + 1 : text.size();
  }
  starts.push_back(text.size());
  return starts;
}

struct Failure {
  std::size_t row;
  std::string what;
};

/// Rows [first, last) into `out` (itemsize bytes each); the first failure, if any.
std::optional<Failure> parse_rows(const std::string& text, const std::vector<std::size_t>& starts, std::size_t first, std::size_t last,
                                  const std::vector<Column>& cols, char* out, std::size_t itemsize) {
  for (std::size_t r = first; r < last; ++r) {
    const char* p = text.data() + starts[r];
    const char* end = text.data() + starts[r + 1];
    while (end > p && (end[-1] == '\n' || end[-1] == '\r')) --end;
    char* row = out + r * itemsize;
    for (std::size_t c = 0; c < cols.size(); ++c) {
      if (c > 0) {
        if (p == end || *p != ',') return Failure{r, fmt::format("{} cells, the header has {} columns", c, cols.size())};
        ++p;
      }
      const char* cell = p;
      while (p < end && *p != ',') ++p;
      const char* digits = cell + (cell < p && *cell == '+' && p - cell > 1 && cell[1] != '-');  // "+1" as strtod reads it
      double v = 0;
      std::from_chars_result res{};
      if (cols[c].kind == Kind::i64) {
        std::int64_t i = 0;
        res = std::from_chars(digits, p, i);
        if (res.ec == std::errc() && res.ptr == p) {
          std::memcpy(row + cols[c].offset, &i, sizeof i);
          continue;
        }
      }
      res = std::from_chars(digits, p, v);
      if (res.ec != std::errc() || res.ptr != p || digits == p)
        return Failure{r, fmt::format("column {} '{}': '{}' is not a number", c + 1, cols[c].name, std::string(cell, p))};
      if (cols[c].kind == Kind::f64) {
        std::memcpy(row + cols[c].offset, &v, sizeof v);
      } else if (cols[c].kind == Kind::i64) {
        const auto i = static_cast<std::int64_t>(v);
        std::memcpy(row + cols[c].offset, &i, sizeof i);
      } else {
        row[cols[c].offset] = v != 0.0 ? 1 : 0;
      }
    }
    if (p != end) return Failure{r, fmt::format("more cells than the header's {} columns", cols.size())};
  }
  return std::nullopt;
}

}  // namespace

py::array read_table(const std::string& path, const py::dtype& dtype) {
  const std::vector<Column> cols = columns_of(dtype, path);
  std::string text;
  std::vector<std::size_t> starts;
  {
    py::gil_scoped_release unlocked;
    text = read_file(path);
    starts = row_starts(text);
  }
  const std::size_t rows = starts.size() - 1;
  py::array out(dtype, std::vector<py::ssize_t>{static_cast<py::ssize_t>(rows)});
  char* data = static_cast<char*>(out.mutable_data());
  const auto itemsize = static_cast<std::size_t>(dtype.itemsize());
  std::optional<Failure> failure;
  {
    py::gil_scoped_release unlocked;
    // two threads over a large table (the flight's own log writer is two threads, too)
    const std::size_t half = rows >= 4096 ? rows / 2 : rows;
    std::optional<Failure> second;
    std::thread other;
    if (half < rows) other = std::thread([&] { second = parse_rows(text, starts, half, rows, cols, data, itemsize); });
    failure = parse_rows(text, starts, 0, half, cols, data, itemsize);
    if (other.joinable()) other.join();
    if (!failure) failure = second;
  }
  if (failure) throw ConfigError(fmt::format("{}:{}: {}", path, failure->row + 2, failure->what));
  return out;
}

}  // namespace tern::core::python
