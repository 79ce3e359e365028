// core/apps/dds/src/rcl_convert.cpp: see rcl_convert.hpp.
#include "rcl_convert.hpp"

#include <cmath>
#include <sstream>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "config/config.hpp"

namespace tern::core::ddsi {

rcl_interfaces::msg::ParameterValue to_rcl(const ParamValue& v) {
  rcl_interfaces::msg::ParameterValue o;
  o.type(rcl_type(v));
  std::visit(
      [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, bool>)
          o.bool_value(x);
        else if constexpr (std::is_same_v<T, std::int64_t>)
          o.integer_value(x);
        else if constexpr (std::is_same_v<T, double>)
          o.double_value(x);
        else if constexpr (std::is_same_v<T, std::string>)
          o.string_value(x);
        else
          o.double_array_value(x);
      },
      v);
  return o;
}

std::uint8_t rcl_type(const ParamValue& v) {
  static constexpr std::uint8_t kTypes[] = {kBool, kInteger, kDouble, kString, kDoubleArray};  // ParamValue's order
  return kTypes[v.index()];
}

ParamValue from_rcl(const rcl_interfaces::msg::ParameterValue& v) {
  switch (v.type()) {
    case kBool: return v.bool_value();
    case kInteger: return static_cast<std::int64_t>(v.integer_value());
    case kDouble: return v.double_value();
    case kString: return v.string_value();
    case kDoubleArray: return v.double_array_value();
    case kIntegerArray: return std::vector<double>(v.integer_array_value().begin(), v.integer_array_value().end());
    default: throw DdsError(fmt::format("parameter type {} (rcl_interfaces/msg/ParameterType) is not one tern has", v.type()));
  }
}

namespace {
/// `text` (a value as to_string writes it) read as a value of `like`'s type.
ParamValue parse_like(const ParamValue& like, const std::string& text) {
  ParamValue v = to_param_value(YAML::Load(text), "vehicle", "default");
  if (std::holds_alternative<double>(like) && std::holds_alternative<std::int64_t>(v))
    return static_cast<double>(std::get<std::int64_t>(v));
  if (std::holds_alternative<std::string>(like) && !std::holds_alternative<std::string>(v)) return text;
  return v;
}
}  // namespace

rcl_interfaces::msg::ParameterDescriptor describe(const ParamBase& p) {
  const ParamSpec& s = p.spec();
  rcl_interfaces::msg::ParameterDescriptor d;
  d.name(p.name());
  d.type(rcl_type(p.default_value()));
  d.description(s.description);
  std::string c = "unit: " + (s.unit.empty() ? "-" : s.unit) + "; default: " + to_string(p.default_value());
  if (!s.choices.empty()) {
    c += "; one of:";
    for (const auto& x : s.choices) c += " " + x;
  }
  if (s.size > 0) c += fmt::format("; size: {}", s.size);
  d.additional_constraints(c);
  d.read_only(!s.live);
  d.dynamic_typing(false);
  if (std::isfinite(s.min) && std::isfinite(s.max)) {
    if (d.type() == kInteger) {
      rcl_interfaces::msg::IntegerRange r;
      r.from_value(static_cast<std::int64_t>(std::ceil(s.min)));
      r.to_value(static_cast<std::int64_t>(std::floor(s.max)));
      r.step(0);
      d.integer_range({r});
    } else if (d.type() == kDouble || d.type() == kDoubleArray) {
      rcl_interfaces::msg::FloatingPointRange r;
      r.from_value(s.min);
      r.to_value(s.max);
      r.step(0);
      d.floating_point_range({r});
    }
  }
  return d;
}

DdsParam from_rcl(const std::string& qualified, const rcl_interfaces::msg::ParameterValue& value,
                  const rcl_interfaces::msg::ParameterDescriptor& d) {
  DdsParam p;
  p.name = qualified;
  p.value = from_rcl(value);
  p.description = d.description();
  p.default_value = p.value;
  p.min = -INFINITY;
  p.max = INFINITY;
  if (!d.floating_point_range().empty()) {
    p.min = d.floating_point_range()[0].from_value();
    p.max = d.floating_point_range()[0].to_value();
  } else if (!d.integer_range().empty()) {
    p.min = static_cast<double>(d.integer_range()[0].from_value());
    p.max = static_cast<double>(d.integer_range()[0].to_value());
  }
  std::istringstream in(d.additional_constraints());
  for (std::string part; std::getline(in, part, ';');) {
    while (!part.empty() && part.front() == ' ') part.erase(part.begin());
    if (part.rfind("unit: ", 0) == 0) p.unit = part.substr(6) == "-" ? "" : part.substr(6);
    if (part.rfind("default: ", 0) == 0) {
      try {
        p.default_value = parse_like(p.value, part.substr(9));
      } catch (const std::exception&) {
      }
    }
  }
  p.read_only = d.read_only();
  return p;
}

}  // namespace tern::core::ddsi
