// core/apps/dds/tern_msgs_gen/idl_scalar.hpp: the IDL type of a C++ scalar on tern's wire (bool
// boolean, double, float, an integer (u)int8..64, an enum its underlying type's).
#pragma once

#include <string>
#include <type_traits>

namespace tern::msgs_gen {

template <class T>
std::string idl_scalar() {
  if constexpr (std::is_enum_v<T>)
    return idl_scalar<std::underlying_type_t<T>>();
  else if constexpr (std::is_same_v<T, bool>)
    return "boolean";
  else if constexpr (std::is_same_v<T, double>)
    return "double";
  else if constexpr (std::is_same_v<T, float>)
    return "float";
  else
    return std::string(std::is_signed_v<T> ? "int" : "uint") + std::to_string(8 * sizeof(T));
}

}  // namespace tern::msgs_gen
