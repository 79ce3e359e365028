// tern/reflect.hpp: field descriptions of message structs, their layout fingerprint and the
// flat column layout used by the flight log.
//
// A message struct `M` describes its fields once, in a static template member:
//
//   template <class V> static constexpr void describe(V& v) {
//     v(&M::stamp, "stamp", "ns");
//     v(&M::accel, "accel", "m/s^2", "x,y,z");   // Eigen vector: one column per component
//   }
//
// plus `static constexpr std::string_view type_name`. From that, tern derives
//  - fingerprint<M>(): a 64-bit FNV-1a hash of the type name, every field's name, kind and
//    element count, nested message layouts, and sizeof(M). Two builds whose M differ in any of
//    these get different fingerprints; the host refuses to bind ports whose fingerprints differ.
//  - layout<M>(): flat columns (name, unit, scalar kind, byte offset) used to log any message
//    without code from the plugin that defined it.
//
// Supported field types: bool, integral and enum types, float, double, std::array of those,
// Eigen::Matrix<double, N, 1>, Eigen::Quaterniond (columns w, x, y, z), and nested described
// structs or std::array of them, and std::array<char, N> text (part of the fingerprint, not
// logged as columns).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "tern/fnv1a.hpp"

namespace tern::reflect {

/// Scalar kinds that a log column can hold.
enum class Scalar : std::uint8_t { f64, f32, i64, i32, i16, i8, u64, u32, u16, u8, boolean };

constexpr std::size_t scalar_size(Scalar s) {
  switch (s) {
    case Scalar::f64:
    case Scalar::i64:
    case Scalar::u64: return 8;
    case Scalar::f32:
    case Scalar::i32:
    case Scalar::u32: return 4;
    case Scalar::i16:
    case Scalar::u16: return 2;
    default: return 1;
  }
}

template <class T>
constexpr Scalar scalar_of() {
  if constexpr (std::is_enum_v<T>) {
    return scalar_of<std::underlying_type_t<T>>();
  } else if constexpr (std::is_same_v<T, bool>) {
    return Scalar::boolean;
  } else if constexpr (std::is_same_v<T, double>) {
    return Scalar::f64;
  } else if constexpr (std::is_same_v<T, float>) {
    return Scalar::f32;
  } else if constexpr (std::is_integral_v<T> && std::is_signed_v<T>) {
    return sizeof(T) == 8 ? Scalar::i64 : sizeof(T) == 4 ? Scalar::i32 : sizeof(T) == 2 ? Scalar::i16 : Scalar::i8;
  } else if constexpr (std::is_integral_v<T>) {
    return sizeof(T) == 8 ? Scalar::u64 : sizeof(T) == 4 ? Scalar::u32 : sizeof(T) == 2 ? Scalar::u16 : Scalar::u8;
  } else {
    static_assert(sizeof(T) == 0, "tern::reflect: unsupported scalar field type");
  }
}

template <class T, class = void>
struct is_described : std::false_type {};
template <class T>
struct is_described<T, std::void_t<decltype(T::type_name)>> : std::true_type {};

template <class T>
struct is_std_array : std::false_type {};
template <class T, std::size_t N>
struct is_std_array<std::array<T, N>> : std::true_type {};

template <class T>
struct is_eigen_vec : std::false_type {};
template <int N>
struct is_eigen_vec<Eigen::Matrix<double, N, 1>> : std::true_type {};

// ---- fingerprint ------------------------------------------------------------------------------

using tern::Fnv1a;  // tern/fnv1a.hpp

template <class M>
constexpr std::uint64_t fingerprint();

struct FingerprintVisitor {
  Fnv1a* f;
  template <class M, class F>
  constexpr void operator()(F M::*, std::string_view name, std::string_view unit, std::string_view components = {}) {
    f->bytes(name);
    f->bytes(unit);
    f->bytes(components);
    hash_type<F>();
  }
  template <class F>
  constexpr void hash_type() {
    f->number(sizeof(F));
    if constexpr (is_described<F>::value) {
      f->bytes("struct");
      f->number(fingerprint<F>());
    } else if constexpr (is_std_array<F>::value) {
      f->bytes("array");
      f->number(std::tuple_size_v<F>);
      hash_type<typename F::value_type>();
    } else if constexpr (is_eigen_vec<F>::value) {
      f->bytes("eigen_vec_f64");
      f->number(F::RowsAtCompileTime);
    } else if constexpr (std::is_same_v<F, Eigen::Quaterniond>) {
      f->bytes("quat_f64_xyzw");
    } else {
      f->bytes("scalar");
      f->number(static_cast<std::uint64_t>(scalar_of<F>()));
    }
  }
};

/// Layout fingerprint of a described message type (see the file comment).
template <class M>
constexpr std::uint64_t fingerprint() {
  Fnv1a f;
  f.bytes(M::type_name);
  f.number(sizeof(M));
  FingerprintVisitor v{&f};
  M::describe(v);
  return f.h;
}

// ---- bitwise copy -----------------------------------------------------------------------------

template <class M>
constexpr bool bitwise_copyable();

/// Whether a field type is plain bytes: a scalar, an Eigen fixed-size double vector or
/// quaternion (their storage is the doubles), a described struct that is bitwise_copyable, or a
/// std::array of those.
template <class F>
constexpr bool plain_field() {
  if constexpr (is_described<F>::value)
    return bitwise_copyable<F>();
  else if constexpr (is_std_array<F>::value)
    return plain_field<typename F::value_type>();
  else if constexpr (is_eigen_vec<F>::value || std::is_same_v<F, Eigen::Quaterniond>)
    return true;
  else
    return std::is_arithmetic_v<F> || std::is_enum_v<F>;
}

struct PlainVisitor {
  bool ok = true;
  template <class M, class F>
  constexpr void operator()(F M::*, std::string_view, std::string_view, std::string_view = {}) {
    ok = ok && plain_field<F>();
  }
};

/// Whether a described message may cross a process boundary by memcpy (an isolated instance's
/// ports, core/host/runners/isolation_channel.hpp): every described field is plain bytes (above), and the
/// struct owns nothing (trivially destructible: no string, vector or pointer owner hides in an
/// undescribed member) and has no virtual table. Eigen's vectors are not
/// std::is_trivially_copyable (user-declared copy constructors), hence this check.
template <class M>
constexpr bool bitwise_copyable() {
  if constexpr (!std::is_trivially_destructible_v<M> || std::is_polymorphic_v<M>) {
    return false;
  } else {
    PlainVisitor v;
    M::describe(v);
    return v.ok;
  }
}

// ---- flat column layout -----------------------------------------------------------------------

struct Column {
  std::string name;  ///< e.g. "accel_x"
  std::string unit;  ///< e.g. "m/s^2"
  Scalar kind;
  std::size_t offset;  ///< byte offset in the message object
};

namespace detail {
inline std::vector<std::string> split_components(std::string_view s, std::size_t n) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (!s.empty() && start <= s.size()) {
    const std::size_t comma = s.find(',', start);
    out.emplace_back(s.substr(start, comma == std::string_view::npos ? s.npos : comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (out.size() != n) {
    out.clear();
    for (std::size_t i = 0; i < n; ++i) out.push_back(std::to_string(i));
  }
  return out;
}
}  // namespace detail

template <class M>
struct LayoutVisitor {
  const M* obj;
  std::vector<Column>* cols;
  template <class F>
  void operator()(F M::*member, std::string_view name, std::string_view unit, std::string_view components = {}) {
    const auto* base = reinterpret_cast<const char*>(obj);
    const auto* field = reinterpret_cast<const char*>(&(obj->*member));
    const std::size_t off = static_cast<std::size_t>(field - base);
    std::string n(name), u(unit);
    if constexpr (is_described<F>::value) {
      // nested structs are part of the fingerprint, not log columns
    } else if constexpr (is_std_array<F>::value) {
      using E = typename F::value_type;
      if constexpr (!is_described<E>::value && !is_eigen_vec<E>::value && !std::is_same_v<E, char>) {  // char arrays are text: not logged
        const auto names = detail::split_components(components, std::tuple_size_v<F>);
        for (std::size_t i = 0; i < std::tuple_size_v<F>; ++i)
          cols->push_back({n + "_" + names[i], u, scalar_of<E>(), off + i * sizeof(E)});
      }
    } else if constexpr (is_eigen_vec<F>::value) {
      const auto names = detail::split_components(components, F::RowsAtCompileTime);
      for (int i = 0; i < F::RowsAtCompileTime; ++i)
        cols->push_back({n + "_" + names[static_cast<std::size_t>(i)], u, Scalar::f64, off + static_cast<std::size_t>(i) * sizeof(double)});
    } else if constexpr (std::is_same_v<F, Eigen::Quaterniond>) {
      // Eigen stores x, y, z, w.
      const auto& q = obj->*member;
      auto at = [&](const double* p) { return static_cast<std::size_t>(reinterpret_cast<const char*>(p) - base); };
      cols->push_back({n + "_w", u, Scalar::f64, at(&q.w())});
      cols->push_back({n + "_x", u, Scalar::f64, at(&q.x())});
      cols->push_back({n + "_y", u, Scalar::f64, at(&q.y())});
      cols->push_back({n + "_z", u, Scalar::f64, at(&q.z())});
    } else {
      cols->push_back({n, u, scalar_of<F>(), off});
    }
  }
};

/// Flat log columns of a message type, in declaration order.
template <class M>
std::vector<Column> layout() {
  const M obj{};
  std::vector<Column> cols;
  LayoutVisitor<M> v{&obj, &cols};
  M::describe(v);
  return cols;
}

}  // namespace tern::reflect
