// core/apps/dds/src/rcl_convert.hpp: tern parameters <-> ROS 2 rcl_interfaces messages.
//   value:      ParameterValue (rcl_interfaces/msg/ParameterValue.msg): bool -> PARAMETER_BOOL,
//               int64 -> PARAMETER_INTEGER, double -> PARAMETER_DOUBLE, text -> PARAMETER_STRING,
//               vector -> PARAMETER_DOUBLE_ARRAY (the ParameterType.msg constants);
//   descriptor: ParameterDescriptor.msg: description = the spec's one line; additional_constraints
//               = "unit: U; default: D[; one of: a, b][; size: N]" (ROS 2 has no unit field);
//               read_only for start-only parameters (they change only between flights);
//               floating_point_range / integer_range from the spec's [min, max] when both are
//               finite (step 0: any value), so rqt_reconfigure shows a slider.
#pragma once

#include <string>

#include "dds_bridge.hpp"
#include "rcl_interfaces/msg/ParameterDescriptor.h"
#include "rcl_interfaces/msg/ParameterValue.h"
#include "tern/param.hpp"

namespace tern::core::ddsi {

/// rcl_interfaces/msg/ParameterType.msg
enum RclType : std::uint8_t {
  kNotSet = 0,
  kBool = 1,
  kInteger = 2,
  kDouble = 3,
  kString = 4,
  kByteArray = 5,
  kBoolArray = 6,
  kIntegerArray = 7,
  kDoubleArray = 8,
  kStringArray = 9,
};

rcl_interfaces::msg::ParameterValue to_rcl(const ParamValue& v);
/// Throws DdsError for a type tern has no parameter of (NOT_SET, byte/bool/integer/string arrays;
/// an integer array is taken as doubles).
ParamValue from_rcl(const rcl_interfaces::msg::ParameterValue& v);
std::uint8_t rcl_type(const ParamValue& v);
rcl_interfaces::msg::ParameterDescriptor describe(const ParamBase& p);

/// The client's view: a parameter from its name, value and descriptor (parses
/// additional_constraints back).
DdsParam from_rcl(const std::string& qualified, const rcl_interfaces::msg::ParameterValue& value,
                  const rcl_interfaces::msg::ParameterDescriptor& d);

}  // namespace tern::core::ddsi
