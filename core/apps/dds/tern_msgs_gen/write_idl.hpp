// core/apps/dds/tern_msgs_gen/write_idl.hpp: the text of one tern_msgs/msg IDL file (what
// fastddsgen -typeros2 reads), from the wire model of its structs (wire_model.hpp).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "wire_model.hpp"

namespace tern::msgs_gen {

/// tern_msgs/msg/<file>.idl: the structs of `all` whose spec names `file`, in their order.
std::string idl_file(std::string_view file, const std::vector<WireStruct>& all);

}  // namespace tern::msgs_gen
