// core/apps/dds/tern_msgs_gen/wire_model.hpp: one tern_msgs message as its IDL struct, read from
// the SDK struct's describe() (tern/reflect.hpp) and its WireSpec (wire_spec.hpp).
//
// How a described field goes on tern's wire (tern_msgs: field for field, in describe()'s order,
// same names):
//   Nanos `stamp` (unit "ns")         std_msgs::msg::Header header  (stamp + epoch; frame_id '')
//   other Nanos in "ns"               builtin_interfaces::msg::Time (value + epoch)
//   bool / integer / enum / double    boolean / (u)intN / the enum's underlying type / double
//   std::array<T, N>, Eigen vector N  T[N], double[N]
//   std::array of described structs   sequence<WireSpec::Sequence::element> (count: its length)
// plus WireSpec's derived field and constants. Any other field type stops the generator's build.
// The generated C++ names the struct msg::<type name after "tern/"> and each field m.<describe()'s
// name>: a struct or describe() name that differs from its C++ name fails tern_dds's build.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "idl_scalar.hpp"
#include "tern/reflect.hpp"
#include "tern/time.hpp"
#include "wire_spec.hpp"

namespace tern::msgs_gen {

enum class Shape { header, time, scalar, array, sequence, derived };

struct WireField {
  std::string name;        ///< the IDL field, e.g. "accel"
  std::string member;      ///< the SDK struct's member (describe()'s name), e.g. "accel"; empty: derived
  std::string idl_type;    ///< of one element: "double", "uint8", "std_msgs::msg::Header", ...
  std::size_t length = 0;  ///< array: elements (double[3]); 0 otherwise
  std::string unit;        ///< describe()'s unit (an IDL comment)
  Shape shape = Shape::scalar;
  std::string cast;  ///< enum: the C++ integer type it has on the wire ("std::uint8_t"); else empty
};

/// One IDL struct of tern_msgs/msg, and the SDK struct it carries.
struct WireStruct {
  std::string name;       ///< "Imu"
  std::string cpp_type;   ///< "msg::Imu"
  std::string tern_type;  ///< "tern/Imu"
  WireSpec spec;
  std::vector<WireField> fields;
};

/// "std::uint8_t" for an enum on std::uint8_t.
template <class T>
std::string cpp_integer() {
  using U = std::underlying_type_t<T>;
  return std::string("std::") + (std::is_signed_v<U> ? "" : "u") + "int" + std::to_string(8 * sizeof(U)) + "_t";
}

template <class M>
struct ModelVisitor {
  const WireSpec* spec;
  std::vector<WireField>* out;
  template <class F>
  void operator()(F M::*, std::string_view name, std::string_view unit, std::string_view = {}) {
    if (spec->omits(name) || name == spec->sequence.length) return;
    WireField f{std::string(name), std::string(name), "", 0, std::string(unit), Shape::scalar, ""};
    if constexpr (std::is_same_v<F, Nanos>) {
      if (unit == "ns") {
        f.shape = name == "stamp" ? Shape::header : Shape::time;
        f.name = name == "stamp" ? "header" : f.name;
        f.idl_type = name == "stamp" ? "std_msgs::msg::Header" : "builtin_interfaces::msg::Time";
        out->push_back(f);
        return;
      }
    }
    add(f, static_cast<F*>(nullptr));
    out->push_back(f);
  }
  template <class F>
  void add(WireField& f, F*) {
    if constexpr (reflect::is_std_array<F>::value) {
      using E = typename F::value_type;
      if constexpr (reflect::is_described<E>::value) {
        f.shape = Shape::sequence;
        f.name = spec->sequence.wire_name;
        f.idl_type = spec->sequence.element;
      } else {
        static_assert(std::is_arithmetic_v<E> && !std::is_same_v<E, char>, "tern_msgs_gen: an array of text or of this type has no wire");
        f.shape = Shape::array;
        f.length = std::tuple_size_v<F>;
        f.idl_type = idl_scalar<E>();
      }
    } else if constexpr (reflect::is_eigen_vec<F>::value) {
      f.shape = Shape::array;
      f.length = F::RowsAtCompileTime;
      f.idl_type = "double";
    } else {
      static_assert(std::is_arithmetic_v<F> || std::is_enum_v<F>, "tern_msgs_gen: this field type has no tern_msgs wire yet");
      f.idl_type = idl_scalar<F>();
      if constexpr (std::is_enum_v<F>) f.cast = cpp_integer<F>();
    }
  }
};

/// The IDL struct of SDK struct M under `spec`.
template <class M>
WireStruct wire_struct(const WireSpec& spec) {
  WireStruct s;
  const std::string_view type = M::type_name;
  s.tern_type = std::string(type);
  s.name = spec.name.empty() ? std::string(type.substr(type.rfind('/') + 1)) : std::string(spec.name);
  s.cpp_type = "msg::" + std::string(type.substr(type.rfind('/') + 1));
  s.spec = spec;
  ModelVisitor<M> v{&spec, &s.fields};
  M::describe(v);
  if (!spec.derived.name.empty())
    s.fields.push_back({std::string(spec.derived.name), "", std::string(spec.derived.idl_type), 0, "", Shape::derived, ""});
  return s;
}

}  // namespace tern::msgs_gen
