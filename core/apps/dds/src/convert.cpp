// core/apps/dds/src/convert.cpp: every tern message the bridge carries and its DDS counterparts
// (all_types()): tern's own (tern_msgs, generated from describe(): tern_msgs_convert.cpp), then
// ROSplane's (convert_rosplane.cpp), then rosflight_io's and sensor_msgs (convert_ros.cpp).
#include <string>
#include <vector>

#include "convert_rosplane.hpp"
#include "convert_util.hpp"
#include "tern_msgs_convert.hpp"

namespace tern::core::ddsi {

namespace {

/// tern_msgs first: find_type() without a ROS type gives tern's own where tern has one.
std::vector<TypeEntry> build() {
  std::vector<TypeEntry> v;
  add_tern_msgs_types(v);
  add_rosplane_types(v);
  add_ros_types(v);
  return v;
}

}  // namespace

std::string ros_type_name(const std::string& dds_type) {
  std::string out;
  for (std::size_t i = 0; i < dds_type.size();) {
    if (dds_type.compare(i, 8, "::dds_::") == 0) {
      out += '/';
      i += 8;
    } else if (dds_type.compare(i, 2, "::") == 0) {
      out += '/';
      i += 2;
    } else {
      out += dds_type[i++];
    }
  }
  if (!out.empty() && out.back() == '_') out.pop_back();
  return out;
}

const std::vector<TypeEntry>& all_types() {
  static const std::vector<TypeEntry> types = build();
  return types;
}

const TypeEntry* find_type(std::string_view tern_type, std::string_view ros_type) {
  for (const auto& e : all_types())
    if (e.tern_type == tern_type && (ros_type.empty() || e.ros_type == ros_type)) return &e;
  return nullptr;
}

const TypeEntry* find_dds_type(std::string_view dds_type) {
  for (const auto& e : all_types())
    if (e.dds_type == dds_type) return &e;
  return nullptr;
}

}  // namespace tern::core::ddsi
