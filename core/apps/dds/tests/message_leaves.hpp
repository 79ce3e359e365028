// core/apps/dds/tests/message_leaves.hpp: the SDK structs the DDS bridge carries and their
// described fields as leaves (one scalar each, at a byte offset in the struct), for the tests
// that fill a message field by field (test_message_definitions.cpp, test_wire_bytes.cpp).
#pragma once

#include <cstddef>
#include <cstring>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "tern/msg/all.hpp"
#include "tern/reflect.hpp"

namespace tern::dds_test {

/// The SDK structs the bridge may carry (every tern_type of all_types() must be one of them).
using Messages =
    std::tuple<msg::State, msg::ControllerCommand, msg::ControllerInternals, msg::CurrentPath, msg::Waypoint, msg::WaypointList,
               msg::Actuators, msg::FlightPhase, msg::Imu, msg::Gnss, msg::Baro, msg::DiffPressure, msg::Mag, msg::Rc, msg::FcuStatus>;

template <class F, std::size_t I = 0>
bool with_message(std::string_view type_name, F&& f) {
  if constexpr (I == std::tuple_size_v<Messages>) {
    return false;
  } else {
    using M = std::tuple_element_t<I, Messages>;
    if (M::type_name == type_name) {
      f(static_cast<M*>(nullptr));
      return true;
    }
    return with_message<F, I + 1>(type_name, std::forward<F>(f));
  }
}

struct Leaf {
  std::string path;   ///< "items.w": the field as kWires names it
  std::string label;  ///< "items[1].w[2]"
  reflect::Scalar kind;
  std::size_t offset;
};

/// Elements of an array of messages given a value (WaypointList: items[0], items[1]; count = 2).
inline constexpr std::size_t kItems = 2;

template <class M>
void leaves(std::vector<Leaf>& out, const std::string& path, const std::string& label, std::size_t base);

template <class M>
struct LeafVisitor {
  std::vector<Leaf>* out;
  std::string path, label;
  std::size_t base;
  template <class F>
  void operator()(F M::*member, std::string_view name, std::string_view, std::string_view = {}) {
    const M obj{};
    const std::size_t off =
        base + static_cast<std::size_t>(reinterpret_cast<const char*>(&(obj.*member)) - reinterpret_cast<const char*>(&obj));
    const std::string p = path + std::string(name), l = label + std::string(name);
    if constexpr (reflect::is_described<F>::value) {
      leaves<F>(*out, p + ".", l + ".", off);
    } else if constexpr (reflect::is_std_array<F>::value) {
      using E = typename F::value_type;
      if constexpr (reflect::is_described<E>::value) {
        for (std::size_t i = 0; i < kItems && i < std::tuple_size_v<F>; ++i)
          leaves<E>(*out, p + ".", l + "[" + std::to_string(i) + "].", off + i * sizeof(E));
      } else {
        for (std::size_t i = 0; i < std::tuple_size_v<F>; ++i)
          out->push_back({p, l + "[" + std::to_string(i) + "]", reflect::scalar_of<E>(), off + i * sizeof(E)});
      }
    } else if constexpr (reflect::is_eigen_vec<F>::value || std::is_same_v<F, Eigen::Quaterniond>) {
      constexpr std::size_t n = sizeof(F) / sizeof(double);
      for (std::size_t i = 0; i < n; ++i)
        out->push_back({p, l + "[" + std::to_string(i) + "]", reflect::Scalar::f64, off + i * sizeof(double)});
    } else {
      out->push_back({p, l, reflect::scalar_of<F>(), off});
    }
  }
};

template <class M>
void leaves(std::vector<Leaf>& out, const std::string& path, const std::string& label, std::size_t base) {
  LeafVisitor<M> v{&out, path, label, base};
  M::describe(v);
}

template <class T>
inline void poke(void* at, T v) {
  std::memcpy(at, &v, sizeof v);
}

/// Writes `value` (a small number, or 0/1 for booleans) into the leaf's scalar.
inline void assign(void* msg, const Leaf& leaf, double value) {
  char* at = static_cast<char*>(msg) + leaf.offset;
  using reflect::Scalar;
  switch (leaf.kind) {
    case Scalar::f64: poke<double>(at, value); break;
    case Scalar::f32: poke<float>(at, static_cast<float>(value)); break;
    case Scalar::i64: poke<std::int64_t>(at, static_cast<std::int64_t>(value)); break;
    case Scalar::i32: poke<std::int32_t>(at, static_cast<std::int32_t>(value)); break;
    case Scalar::i16: poke<std::int16_t>(at, static_cast<std::int16_t>(value)); break;
    case Scalar::i8: poke<std::int8_t>(at, static_cast<std::int8_t>(value)); break;
    case Scalar::u64: poke<std::uint64_t>(at, static_cast<std::uint64_t>(value)); break;
    case Scalar::u32: poke<std::uint32_t>(at, static_cast<std::uint32_t>(value)); break;
    case Scalar::u16: poke<std::uint16_t>(at, static_cast<std::uint16_t>(value)); break;
    case Scalar::u8: poke<std::uint8_t>(at, static_cast<std::uint8_t>(value)); break;
    case Scalar::boolean: poke<bool>(at, value != 0.0); break;
  }
}

inline bool is_float(reflect::Scalar k) { return k == reflect::Scalar::f64 || k == reflect::Scalar::f32; }

/// The first value of every leaf: distinct for floating-point fields (i + 1.25, exact in float),
/// 1 (true) for the others (enumerations stay valid), the number of items given values for `count`.
inline double base_value(const Leaf& leaf, std::size_t i) {
  if (leaf.path == "count") return static_cast<double>(kItems);
  return is_float(leaf.kind) ? static_cast<double>(i) + 1.25 : 1.0;
}

}  // namespace tern::dds_test
