// core/host/graph/message_columns.hpp: a message's log columns (tern/reflect.hpp's layout: name,
// unit, scalar kind, byte offset) read and written as numbers, for what reaches a flight's
// messages by field name from outside C++ (tern.Host's read and write, held messages).
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "tern/reflect.hpp"

namespace tern::core {

namespace detail {
template <class F>
decltype(auto) with_scalar(reflect::Scalar kind, F&& f) {
  using reflect::Scalar;
  switch (kind) {
    case Scalar::f64: return f(double{});
    case Scalar::f32: return f(float{});
    case Scalar::i64: return f(std::int64_t{});
    case Scalar::i32: return f(std::int32_t{});
    case Scalar::i16: return f(std::int16_t{});
    case Scalar::i8: return f(std::int8_t{});
    case Scalar::u64: return f(std::uint64_t{});
    case Scalar::u32: return f(std::uint32_t{});
    case Scalar::u16: return f(std::uint16_t{});
    case Scalar::u8: return f(std::uint8_t{});
    case Scalar::boolean: break;
  }
  return f(bool{});
}
}  // namespace detail

/// Column `c` of the message at `msg` as a double (a boolean: 0 or 1; a 64-bit integer beyond
/// 2^53 rounded to the nearest double).
inline double column_value(const reflect::Column& c, const void* msg) {
  return detail::with_scalar(c.kind, [&](auto zero) {
    decltype(zero) v;
    std::memcpy(&v, static_cast<const char*>(msg) + c.offset, sizeof v);
    return static_cast<double>(v);
  });
}

/// Stores `v` into column `c` of the message at `msg`, converted to the column's kind: a boolean
/// is v != 0, an integer kind takes v truncated toward zero (column_problem() checks it fits).
inline void set_column_value(const reflect::Column& c, void* msg, double v) {
  detail::with_scalar(c.kind, [&](auto zero) {
    const auto x = static_cast<decltype(zero)>(v);
    std::memcpy(static_cast<char*>(msg) + c.offset, &x, sizeof x);
  });
}

/// The column named `name` of `columns`, or nullptr.
const reflect::Column* find_column(const std::vector<reflect::Column>& columns, const std::string& name);

/// Why `v` cannot be stored in column `c` ("" when it can): not finite, or outside the range of
/// an integer kind, or not 0/1 for a boolean.
std::string column_problem(const reflect::Column& c, double v);

/// The column names of `columns`, comma-separated (for an error naming what a message has).
std::string column_names(const std::vector<reflect::Column>& columns);

}  // namespace tern::core
