// core/dds/src/param_convert.hpp: tern parameters <-> tern_msgs ParamValue / ParamInfo.
#pragma once

#include <string>

#include "dds_bridge.hpp"
#include "tern/param.hpp"
#include "tern_msgs/msg/Vehicle.h"

namespace tern::core {

inline tern_msgs::msg::ParamValue to_dds(const ParamValue& v) {
  tern_msgs::msg::ParamValue o;
  o.kind(static_cast<std::uint8_t>(v.index()));  // bool, integer, double, string, double array
  std::visit([&](const auto& x) {
    using T = std::decay_t<decltype(x)>;
    if constexpr (std::is_same_v<T, bool>) o.bool_value(x);
    else if constexpr (std::is_same_v<T, std::int64_t>) o.integer_value(x);
    else if constexpr (std::is_same_v<T, double>) o.double_value(x);
    else if constexpr (std::is_same_v<T, std::string>) o.string_value(x);
    else o.double_array_value(x);
  }, v);
  return o;
}

/// Throws DdsError for an unknown kind.
inline ParamValue from_dds(const tern_msgs::msg::ParamValue& v) {
  switch (v.kind()) {
    case 0: return v.bool_value();
    case 1: return static_cast<std::int64_t>(v.integer_value());
    case 2: return v.double_value();
    case 3: return v.string_value();
    case 4: return v.double_array_value();
    default: throw DdsError("parameter value of unknown kind " + std::to_string(v.kind()));
  }
}

inline tern_msgs::msg::ParamInfo to_info(const std::string& name, const ParamBase& p) {
  tern_msgs::msg::ParamInfo i;
  i.name(name);
  i.value(to_dds(p.value()));
  i.default_value(to_dds(p.default_value()));
  i.unit(p.spec().unit);
  i.min(p.spec().min);
  i.max(p.spec().max);
  i.description(p.spec().description);
  i.choices(p.spec().choices);
  i.size(static_cast<std::uint32_t>(p.spec().size));
  return i;
}

inline DdsParam from_info(const tern_msgs::msg::ParamInfo& i) {
  DdsParam p;
  p.name = i.name();
  p.value = from_dds(i.value());
  p.default_value = from_dds(i.default_value());
  p.unit = i.unit();
  p.description = i.description();
  p.min = i.min();
  p.max = i.max();
  p.choices = i.choices();
  p.size = i.size();
  return p;
}

}  // namespace tern::core
