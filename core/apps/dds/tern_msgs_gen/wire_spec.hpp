// core/apps/dds/tern_msgs_gen/wire_spec.hpp: which SDK structs are tern's own DDS messages
// (tern_msgs/msg) and the little each one's describe() does not say: its IDL file and name, the
// fields it leaves off, a sequence, a derived field, named constants. Everything else about the
// wire comes from describe() (wire_model.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "tern/msg/all.hpp"

namespace tern::msgs_gen {

struct WireSpec {
  std::string_view file;               ///< the IDL file under tern_msgs/msg/, without ".idl": "Sensors"
  std::string_view name;               ///< the IDL struct; empty: the type name after "tern/"
  bool topic = true;                   ///< a ddsi::TypeEntry (published); false: a field of a service request
  bool read = false;                   ///< also read from the wire: from_<name>() (a service request's field)
  std::vector<std::string_view> omit;  ///< described fields not on the wire
  /// An array of described structs as a sequence of a ROS type, converted by hand.
  struct Sequence {
    std::string_view field;      ///< the described array ("items")
    std::string_view wire_name;  ///< the IDL field ("waypoints")
    std::string_view length;     ///< the described field holding the valid count ("count"): not on the wire
    std::string_view element;    ///< the IDL element type ("rosplane_msgs::msg::Waypoint")
    std::string_view include;    ///< the IDL file defining it
    std::string_view convert;    ///< void f(const Item&, const std_msgs::msg::Header& list's, Element&)
    std::string_view render;     ///< std::string f(std::size_t index, const Element&): one text line
    std::string_view header;     ///< the C++ header declaring both (core/apps/dds/src/)
  } sequence;
  /// A field the wire adds, computed from the message `m` (appended last).
  struct Derived {
    std::string_view name, idl_type, expr;
  } derived;
  /// `module <name>_Constants { const <type> <NAME> = <value>; ... }` before the struct.
  std::string_view constants_type;
  std::vector<std::pair<std::string, int>> constants;

  bool omits(std::string_view field) const {
    for (auto f : omit)
      if (f == field) return true;
    return false;
  }
};

/// A spec with only its IDL file (and struct name) set.
inline WireSpec in_file(std::string_view file, std::string_view name = {}) {
  WireSpec s;
  s.file = file;
  s.name = name;
  return s;
}

/// tern_msgs/FlightPhase's constants: each msg::Phase by its name in capitals.
inline std::vector<std::pair<std::string, int>> phase_constants() {
  std::vector<std::pair<std::string, int>> out;
  for (int v = 0; v < 256; ++v) {
    const std::string_view name = msg::phase_name(static_cast<msg::Phase>(v));
    if (name == "unknown") continue;
    std::string upper(name);
    for (char& c : upper) c = static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
    out.emplace_back(upper, v);
  }
  return out;
}

/// Calls v.template message<M>(spec) for each tern_msgs message, in the order of its IDL file.
template <class V>
void tern_msgs_messages(V& v) {
  v.template message<msg::Imu>(in_file("Sensors"));
  v.template message<msg::Gnss>(in_file("Sensors"));
  v.template message<msg::Baro>(in_file("Sensors"));
  v.template message<msg::DiffPressure>(in_file("Sensors"));
  v.template message<msg::Mag>(in_file("Sensors"));
  v.template message<msg::Rc>(in_file("Sensors"));
  v.template message<msg::FcuStatus>(in_file("Sensors"));
  v.template message<msg::Actuators>(in_file("Vehicle"));
  WireSpec phase = in_file("Vehicle");
  phase.derived = {"phase_name", "string", "std::string(msg::phase_name(m.phase))"};
  phase.constants_type = "uint8";
  phase.constants = phase_constants();
  v.template message<msg::FlightPhase>(phase);
  // add_mission_item's item (tern_msgs/srv/Services.idl): msg::Waypoint field for field
  WireSpec item = in_file("Vehicle", "MissionItem");
  item.topic = false;
  item.read = true;
  v.template message<msg::Waypoint>(item);
  // the mission: ROSplane waypoints (the type of each item is the path manager's, not on the wire)
  WireSpec list = in_file("Vehicle");
  list.omit = {"immediate"};
  list.sequence = {"items",
                   "waypoints",
                   "count",
                   "rosplane_msgs::msg::Waypoint",
                   "rosplane_msgs/msg/Waypoint.idl",
                   "list_waypoint",
                   "render_list_waypoint",
                   "convert_rosplane.hpp"};
  v.template message<msg::WaypointList>(list);
}

}  // namespace tern::msgs_gen
