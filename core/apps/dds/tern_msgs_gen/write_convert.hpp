// core/apps/dds/tern_msgs_gen/write_convert.hpp: the C++ of the tern_msgs conversions, from the
// wire model (wire_model.hpp), compiled into tern_dds:
//   tern_msgs_convert.hpp  add_tern_msgs_types(v): a ddsi::TypeEntry (convert, render) per topic
//                          message; to_<name>() / from_<name>() of each message a service carries
//                          (to_mission_item, from_mission_item)
//   tern_msgs_convert.cpp  their definitions: one statement per wire field (convert_util.hpp's
//                          stamp, to_time, vec, Text), in the IDL's order
#pragma once

#include <string>
#include <vector>

#include "wire_model.hpp"

namespace tern::msgs_gen {

std::string convert_header(const std::vector<WireStruct>& all);
std::string convert_source(const std::vector<WireStruct>& all);

}  // namespace tern::msgs_gen
