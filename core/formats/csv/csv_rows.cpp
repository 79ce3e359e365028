#include "csv/csv_rows.hpp"

#include <charconv>
#include <cstdint>
#include <cstring>

namespace tern::core {

namespace {
template <class T>
T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

char* put_cell(char* p, char* end, reflect::Scalar kind, const char* v) {
  using reflect::Scalar;
  switch (kind) {
    case Scalar::f64: return std::to_chars(p, end, load<double>(v)).ptr;
    case Scalar::f32: return std::to_chars(p, end, load<float>(v)).ptr;
    case Scalar::i64: return std::to_chars(p, end, load<std::int64_t>(v)).ptr;
    case Scalar::i32: return std::to_chars(p, end, load<std::int32_t>(v)).ptr;
    case Scalar::i16: return std::to_chars(p, end, load<std::int16_t>(v)).ptr;
    case Scalar::i8: return std::to_chars(p, end, static_cast<int>(load<std::int8_t>(v))).ptr;
    case Scalar::u64: return std::to_chars(p, end, load<std::uint64_t>(v)).ptr;
    case Scalar::u32: return std::to_chars(p, end, load<std::uint32_t>(v)).ptr;
    case Scalar::u16: return std::to_chars(p, end, load<std::uint16_t>(v)).ptr;
    case Scalar::u8: return std::to_chars(p, end, static_cast<unsigned>(load<std::uint8_t>(v))).ptr;
    case Scalar::boolean: *p = load<std::uint8_t>(v) ? '1' : '0'; return p + 1;
  }
  return p;
}
}  // namespace

std::string csv_header(const std::vector<reflect::Column>& columns) {
  std::string header = "t [s]";
  for (const auto& c : columns) header += "," + c.name + " [" + c.unit + "]";
  return header + "\n";
}

char* put_csv_time(char* p, Nanos t) {
  // exact decimal seconds from integer ns: "<s>.<9 digits>"
  if (t < 0) *p++ = '-';
  const std::uint64_t a = t < 0 ? 0ull - static_cast<std::uint64_t>(t) : static_cast<std::uint64_t>(t);
  p = std::to_chars(p, p + 20, a / 1'000'000'000ull).ptr;
  *p++ = '.';
  std::uint64_t frac = a % 1'000'000'000ull;
  for (int i = 8; i >= 0; --i) {
    p[i] = static_cast<char>('0' + frac % 10);
    frac /= 10;
  }
  return p + 9;
}

std::size_t format_csv_rows(const std::vector<reflect::Column>& columns, std::size_t msg_size, std::string_view records,
                            std::unique_ptr<char[]>& out, std::size_t& capacity) {
  const std::size_t rec = sizeof(Nanos) + msg_size;
  const std::size_t rows = records.size() / rec;
  const std::size_t row_max = (columns.size() + 1) * (kMaxCellChars + 1) + 1;
  if (rows * row_max > capacity) {
    capacity = rows * row_max;
    out = std::make_unique_for_overwrite<char[]>(capacity);  // no zero-filling: every byte used is written
  }
  char* p = out.get();
  char* const end = p + capacity;
  for (std::size_t off = 0; off + rec <= records.size(); off += rec) {
    const char* r = records.data() + off;
    p = put_csv_time(p, load<Nanos>(r));
    const char* m = r + sizeof(Nanos);
    for (const auto& c : columns) {
      *p++ = ',';
      p = put_cell(p, end, c.kind, m + c.offset);
    }
    *p++ = '\n';
  }
  return static_cast<std::size_t>(p - out.get());
}

}  // namespace tern::core
