// core/apps/dds/tests/test_message_definitions.cpp (ctest dds_messages): each tern message the DDS
// bridge carries is defined once, by the SDK struct's describe() (sdk/include/tern/msg/); the IDL
// (core/apps/dds/idl/) and the conversions (src/convert.cpp, src/convert_ros.cpp) are checked
// against it, for every entry of ddsi::all_types():
//  1. tern's own wire types (tern_msgs): the IDL struct's fields are describe()'s, same names
//     (`stamp` is the header), IDL types and order.
//  2. ROS's wire types (rosplane_msgs, rosflight_msgs, sensor_msgs: fixed by ROS, checked against
//     their .msg files by ctest dds): every described field reaches an IDL field and every IDL
//     field is filled from one, unless kWires below says why not.
//  3. the conversion: a message with a value in every field is converted and serialized; then
//     each field alone is changed: the bytes on the wire must change, and must stay the same for
//     a field kWires lists as not on that wire.
// A field added to the struct, the IDL or a conversion alone fails one of these.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "dds_internal.hpp"
#include "mission_item.hpp"
#include "tern/msg/all.hpp"
#include "tern/reflect.hpp"
#include "message_leaves.hpp"
#include "wire_samples.hpp"

using namespace tern;
namespace ddsi = tern::core::ddsi;
namespace fs = std::filesystem;
using namespace tern::dds_test;

namespace {

// ---- what each bridged pair carries, beyond "same name" --------------------------------------

/// One entry of all_types(): a tern type on one DDS type. Field names are describe()'s; a nested
/// field is "items.type". `stamp` goes to `header` unless carried_as says otherwise.
struct Wire {
  std::string tern_type, wire_struct;
  std::map<std::string, std::string> carried_as;   ///< field -> wire fields "a,b", or "(how)" when no field holds it
  std::map<std::string, std::string> not_on_wire;  ///< field -> why
  std::map<std::string, std::string> wire_only;    ///< wire field -> what fills it
};

const std::string kNotInRosplane = "ROSplane's message has no such field";
const std::string kWaypointItem = "ROSplane's Waypoint has no mission item type";

const std::vector<Wire> kWires = {
    {"tern/State",
     "rosplane_msgs::msg::State",
     {{"u", "v_x"},
      {"v", "v_y"},
      {"w", "v_z"},
      {"Va", "va"},
      {"origin_lat", "initial_lat"},
      {"origin_lon", "initial_lon"},
      {"origin_alt", "initial_alt"}},
     {{"v_n", kNotInRosplane},
      {"v_e", kNotInRosplane},
      {"v_d", kNotInRosplane},
      {"Vg", kNotInRosplane},
      {"gamma", kNotInRosplane},
      {"w_d", kNotInRosplane},
      {"origin_valid", kNotInRosplane},
      {"valid", kNotInRosplane},
      {"status", kNotInRosplane},
      {"degraded_sensors", kNotInRosplane},
      {"P_diag", kNotInRosplane}},
     {}},
    {"tern/ControllerCommand",
     "rosplane_msgs::msg::ControllerCommands",
     {{"Va_c", "va_c"}},
     {{"override_phi", kNotInRosplane}, {"override_theta", kNotInRosplane}, {"landing", kNotInRosplane}, {"h_td", kNotInRosplane}},
     {}},
    {"tern/ControllerInternals", "rosplane_msgs::msg::ControllerInternals", {}, {{"delta_t_c", kNotInRosplane}}, {}},
    {"tern/CurrentPath",
     "rosplane_msgs::msg::CurrentPath",
     {{"Va_d", "va_d"}, {"lambda", "lamda"}},
     {{"waypoint_index", kNotInRosplane},
      {"landing", kNotInRosplane},
      {"flare_height", kNotInRosplane},
      {"decision_height", kNotInRosplane},
      {"attempt", kNotInRosplane}},
     {}},
    {"tern/Waypoint",
     "rosplane_msgs::msg::Waypoint",
     {{"Va_d", "va_d"}},
     {{"type", kWaypointItem},
      {"loiter_radius", kWaypointItem},
      {"loiter_direction", kWaypointItem},
      {"loiter_time", kWaypointItem},
      {"loiter_turns", kWaypointItem},
      {"land_glide_slope", kWaypointItem},
      {"land_flare_height", kWaypointItem},
      {"land_decision_height", kWaypointItem}},
     {{"header", "zero: tern's Waypoint has no stamp"}, {"set_current", "false"}, {"clear_wp_list", "false"}}},
    {"tern/WaypointList",
     "tern_msgs::msg::WaypointList",
     {{"count", "(the length of waypoints)"}, {"items", "waypoints"}},
     {{"immediate", "the path manager's own switch"},
      {"items.type", kWaypointItem},
      {"items.loiter_radius", kWaypointItem},
      {"items.loiter_direction", kWaypointItem},
      {"items.loiter_time", kWaypointItem},
      {"items.loiter_turns", kWaypointItem},
      {"items.land_glide_slope", kWaypointItem},
      {"items.land_flare_height", kWaypointItem},
      {"items.land_decision_height", kWaypointItem}},
     {}},
    {"tern/WaypointList",
     "rosplane_msgs::msg::Waypoint",  // waypoint_path: a clear, then one sample per item
     {{"count", "(one sample per item)"}, {"items", "w,lla,chi_d,use_chi,va_d"}},
     {{"revision", kNotInRosplane},
      {"loop", kNotInRosplane},
      {"loops", kNotInRosplane},
      {"immediate", kNotInRosplane},
      {"items.type", kWaypointItem},
      {"items.loiter_radius", kWaypointItem},
      {"items.loiter_direction", kWaypointItem},
      {"items.loiter_time", kWaypointItem},
      {"items.loiter_turns", kWaypointItem},
      {"items.land_glide_slope", kWaypointItem},
      {"items.land_flare_height", kWaypointItem},
      {"items.land_decision_height", kWaypointItem}},
     {{"set_current", "false"}, {"clear_wp_list", "true on the first sample (the clear)"}}},
    {"tern/Actuators", "tern_msgs::msg::Actuators", {}, {}, {}},
    {"tern/FlightPhase", "tern_msgs::msg::FlightPhase", {}, {}, {{"phase_name", "msg::phase_name(phase)"}}},
    {"tern/Imu", "tern_msgs::msg::Imu", {}, {}, {}},
    {"tern/Gnss", "tern_msgs::msg::Gnss", {}, {}, {}},
    {"tern/Baro", "tern_msgs::msg::Baro", {}, {}, {}},
    {"tern/DiffPressure", "tern_msgs::msg::DiffPressure", {}, {}, {}},
    {"tern/Mag", "tern_msgs::msg::Mag", {}, {}, {}},
    {"tern/Rc", "tern_msgs::msg::Rc", {}, {}, {}},
    {"tern/FcuStatus", "tern_msgs::msg::FcuStatus", {}, {}, {}},
    {"tern/Imu",
     "sensor_msgs::msg::Imu",
     {{"accel", "linear_acceleration"}, {"gyro", "angular_velocity"}},
     {{"temperature", "sensor_msgs/Imu has no temperature"}},
     {{"orientation", "identity: tern's Imu has no attitude"},
      {"orientation_covariance", "[0] = -1: no orientation estimate"},
      {"angular_velocity_covariance", "zeros: unknown"},
      {"linear_acceleration_covariance", "zeros: unknown"}}},
    {"tern/Mag", "sensor_msgs::msg::MagneticField", {{"field", "magnetic_field"}}, {}, {{"magnetic_field_covariance", "zeros: unknown"}}},
    {"tern/Baro", "rosflight_msgs::msg::Barometer", {{"pressure", "altitude,pressure"}}, {}, {}},
    {"tern/DiffPressure", "rosflight_msgs::msg::Airspeed", {{"pressure", "velocity,differential_pressure"}}, {}, {}},
    {"tern/Gnss",
     "rosflight_msgs::msg::GNSS",
     {{"time_of_validity", "header,gnss_unix_seconds,gnss_unix_nanos"},
      {"num_sats", "num_sat"},
      {"vel", "vel_n,vel_e,vel_d"},
      {"h_acc", "horizontal_accuracy"},
      {"v_acc", "vertical_accuracy"},
      {"s_acc", "speed_accuracy"}},
     {{"stamp", "header.stamp is the time of validity, as rosflight_io's"}},
     {}},
    {"tern/FcuStatus",
     "rosflight_msgs::msg::Status",
     {{"error_code", "error_code,num_errors"}},
     {{"battery_voltage", "ROSflight's Status has no battery"}, {"battery_current", "ROSflight's Status has no battery"}},
     {{"control_mode", "0: pass-through, the only mode tern flies"}, {"loop_time_us", "0: tern's FcuStatus has none"}}},
    {"tern/Actuators",
     "rosflight_msgs::msg::Command",
     {{"delta_a", "u"}, {"delta_e", "u"}, {"delta_r", "u"}, {"delta_t", "u"}},
     {{"brake", "rosflight_io's Command drives the mixer's four channels; wheel brakes are an aux output it does not name"}},
     {{"mode", "0: pass-through"}, {"ignore", "0: none"}}},
};

// ---- the IDL ------------------------------------------------------------------------------------

struct Field {
  std::string name, type;  ///< type as written in the IDL, "[N]" appended for arrays
  bool operator==(const Field&) const = default;
};
using Structs = std::map<std::string, std::vector<Field>>;  ///< "pkg::msg::Name" -> fields in order

/// Every struct of every .idl under `root` (the subset of IDL our files use: modules, structs,
/// one member per line, constants).
Structs read_idl(const fs::path& root) {
  Structs out;
  const std::regex open(R"(^\s*(module|struct)\s+(\w+)\s*\{)"), close(R"(^\s*\}\s*;)"),
      member(R"(^\s*([\w:<>]+)\s+(\w+)\s*(\[\s*(\d+)\s*\])?\s*;)");
  for (const auto& f : fs::recursive_directory_iterator(root)) {
    if (f.path().extension() != ".idl") continue;
    std::ifstream in(f.path());
    std::vector<std::pair<std::string, std::string>> scopes;  // (module|struct, name)
    std::string line;
    while (std::getline(in, line)) {
      line = line.substr(0, line.find("//"));
      std::smatch m;
      if (std::regex_search(line, m, open)) {
        scopes.emplace_back(m[1], m[2]);
      } else if (std::regex_search(line, m, close)) {
        if (!scopes.empty()) scopes.pop_back();
      } else if (!scopes.empty() && scopes.back().first == "struct" && std::regex_search(line, m, member)) {
        std::string name;
        for (const auto& s : scopes) {
          if (!name.empty()) name += "::";
          name += s.second;
        }
        out[name].push_back({m[2], m[1].str() + (m[3].matched ? "[" + m[4].str() + "]" : "")});
      }
    }
  }
  return out;
}

/// "rosplane_msgs::msg::dds_::State_" -> "rosplane_msgs::msg::State".
std::string wire_struct(const std::string& dds_type) {
  std::string s = std::regex_replace(dds_type, std::regex("dds_::"), "");
  if (!s.empty() && s.back() == '_') s.pop_back();
  return s;
}

// ---- describe() as IDL -----------------------------------------------------------------------

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

/// The IDL type a described field of type F has on tern's own wire.
template <class F>
std::string idl_type(std::string_view name, std::string_view unit) {
  if constexpr (std::is_same_v<F, Nanos>) {
    if (unit == "ns") return name == "stamp" ? "std_msgs::msg::Header" : "builtin_interfaces::msg::Time";
  }
  if constexpr (reflect::is_described<F>::value) {
    return wire_struct(ddsi::find_type(F::type_name)->dds_type);
  } else if constexpr (reflect::is_std_array<F>::value) {
    using E = typename F::value_type;
    if constexpr (reflect::is_described<E>::value)
      return "sequence<" + idl_type<E>("", "") + ">";
    else
      return idl_scalar<E>() + "[" + std::to_string(std::tuple_size_v<F>) + "]";
  } else if constexpr (reflect::is_eigen_vec<F>::value) {
    return "double[" + std::to_string(F::RowsAtCompileTime) + "]";
  } else if constexpr (std::is_same_v<F, Eigen::Quaterniond>) {
    return "geometry_msgs::msg::Quaternion";
  } else {
    return idl_scalar<F>();
  }
}

struct Described {
  std::string name, idl_type;
};

template <class M>
struct DescribeVisitor {
  std::vector<Described>* out;
  template <class F>
  void operator()(F M::*, std::string_view name, std::string_view unit, std::string_view = {}) {
    out->push_back({std::string(name), idl_type<F>(name, unit)});
  }
};

template <class M>
std::vector<Described> described(M*) {
  std::vector<Described> out;
  DescribeVisitor<M> v{&out};
  M::describe(v);
  return out;
}

/// The wire fields a described field goes to ("(how)": none).
std::vector<std::string> targets(const Wire& w, const std::string& field) {
  auto it = w.carried_as.find(field);
  const std::string t = it != w.carried_as.end() ? it->second : field == "stamp" ? "header" : field;
  std::vector<std::string> out;
  if (t.empty() || t.front() == '(') return out;
  std::stringstream ss(t);
  for (std::string s; std::getline(ss, s, ',');) out.push_back(s);
  return out;
}

std::string field_list(const std::vector<Field>& v) {
  std::string s;
  for (const auto& f : v) {
    if (!s.empty()) s += ", ";
    s += f.type + " " + f.name;
  }
  return s;
}

/// Other values of a leaf, any of which a conversion that carries the field must tell apart.
std::vector<double> other_values(const Leaf& leaf, double base) {
  if (leaf.kind == reflect::Scalar::boolean) return {0.0};
  if (is_float(leaf.kind)) return {base + 0.5, base + 1000.5};
  return {base + 1, base + 2, base + 3};  // an enumeration may map several values to one (ROSplane's alt_zone)
}

/// Every sample the entry writes for `m`, serialized as on the wire.
std::vector<unsigned char> wire_bytes(const ddsi::TypeEntry& e, const void* m) {
  std::vector<unsigned char> out;
  for (const auto& s : wire_samples(e, m, 0)) {
    REQUIRE(!s.bytes.empty());
    out.insert(out.end(), s.bytes.begin(), s.bytes.end());
  }
  return out;
}

/// Whether kWires lists the leaf (or the field holding it) as not on this wire.
bool listed_not_on_wire(const Wire& w, const std::string& path) {
  for (std::string p = path;; p = p.substr(0, p.rfind('.'))) {
    if (w.not_on_wire.count(p)) return true;
    if (p.find('.') == std::string::npos) return false;
  }
}

const Wire* find_wire(const ddsi::TypeEntry& e) {
  for (const auto& w : kWires)
    if (w.tern_type == e.tern_type && w.wire_struct == wire_struct(e.dds_type)) return &w;
  return nullptr;
}

}  // namespace

TEST_CASE("dds messages: every bridged pair is listed, and every listed pair is bridged") {
  for (const auto& e : ddsi::all_types()) {
    const std::string tern_type(e.tern_type);
    CHECK_MESSAGE(find_wire(e) != nullptr, tern_type, " on ", e.dds_type, ": add it to kWires");
    CHECK_MESSAGE(with_message(e.tern_type, [](auto*) {}), tern_type, ": add its struct to Messages");
  }
  for (const auto& w : kWires) {
    bool bridged = false;
    for (const auto& e : ddsi::all_types()) bridged = bridged || find_wire(e) == &w;
    CHECK_MESSAGE(bridged, w.tern_type, " on ", w.wire_struct, " is no longer bridged: remove it from kWires");
  }
}

TEST_CASE("dds messages: the IDL has describe()'s fields (tern_msgs: same names, types, order)") {
  const Structs idl = read_idl(TERN_DDS_IDL_DIR);
  for (const auto& e : ddsi::all_types()) {
    const Wire* w = find_wire(e);
    if (w == nullptr) continue;  // reported above
    CAPTURE(w->tern_type);
    CAPTURE(w->wire_struct);
    REQUIRE_MESSAGE(idl.count(w->wire_struct), "no struct ", w->wire_struct, " in ", TERN_DDS_IDL_DIR);
    const auto& wire = idl.at(w->wire_struct);
    with_message(e.tern_type, [&](auto* tag) {
      const auto fields = described(tag);
      std::set<std::string> names;
      for (const auto& f : fields) names.insert(f.name);
      for (const auto& [field, why] : w->carried_as) CHECK_MESSAGE(names.count(field), "kWires names no field '", field, "' of the struct");
      for (const auto& [field, why] : w->not_on_wire)
        CHECK_MESSAGE(names.count(field.substr(0, field.find('.'))), "kWires names no field '", field, "' of the struct");
      std::vector<Field> want;  // the wire fields describe() says, in its order
      std::set<std::string> reached;
      for (const auto& f : fields) {
        if (w->not_on_wire.count(f.name)) continue;
        for (const auto& t : targets(*w, f.name)) {
          if (reached.insert(t).second) want.push_back({t, f.idl_type});
        }
      }
      std::vector<Field> have;  // the IDL's fields that come from the struct
      for (const auto& f : wire) {
        if (w->wire_only.count(f.name)) continue;
        have.push_back(f);
      }
      for (const auto& [field, why] : w->wire_only) {
        bool found = false;
        for (const auto& f : wire) found = found || f.name == field;
        CHECK_MESSAGE(found, "kWires names no field '", field, "' of ", w->wire_struct);
      }
      if (w->wire_struct.rfind("tern_msgs::", 0) == 0) {
        CHECK_MESSAGE(have == want, "\n  IDL:        ", field_list(have), "\n  describe(): ", field_list(want));
      } else {  // ROS's wire: names only (ROS narrows, splits and renames), in any order
        std::set<std::string> idl_names;
        for (const auto& f : have) idl_names.insert(f.name);
        for (const auto& f : want) CHECK_MESSAGE(idl_names.count(f.name), "field for '", f.name, "' is not in the IDL");
        for (const auto& f : have) CHECK_MESSAGE(reached.count(f.name), "IDL field '", f.name, "' is filled from no described field");
      }
    });
  }
}

TEST_CASE("dds messages: each conversion carries every described field, and only those kWires allows it to drop") {
  for (const auto& e : ddsi::all_types()) {
    const Wire* w = find_wire(e);
    if (w == nullptr) continue;
    with_message(e.tern_type, [&](auto* tag) {
      using M = std::remove_pointer_t<decltype(tag)>;
      std::vector<Leaf> all;
      leaves<M>(all, "", "", 0);
      REQUIRE(!all.empty());
      M m{};
      for (std::size_t i = 0; i < all.size(); ++i) assign(&m, all[i], base_value(all[i], i));
      const auto base = wire_bytes(e, &m);
      REQUIRE(!base.empty());
      for (std::size_t i = 0; i < all.size(); ++i) {
        const Leaf& leaf = all[i];
        const double v0 = base_value(leaf, i);
        bool changed = false;
        for (double v : other_values(leaf, v0)) {
          M other = m;
          assign(&other, leaf, v);
          changed = changed || wire_bytes(e, &other) != base;
        }
        const bool dropped = listed_not_on_wire(*w, leaf.path);
        CHECK_MESSAGE(
            changed != dropped, std::string(e.tern_type), " -> ", e.ros_type, ": field ", leaf.label,
            dropped ? " is listed as not on this wire but reaches it" : " does not reach the wire (convert.cpp / convert_ros.cpp)");
      }
    });
  }
}

TEST_CASE("dds messages: tern_msgs/MissionItem (add_mission_item) is msg::Waypoint field for field, and carries each field both ways") {
  const Structs idl = read_idl(TERN_DDS_IDL_DIR);
  REQUIRE(idl.count("tern_msgs::msg::MissionItem"));
  std::vector<Field> want;
  for (const auto& f : described(static_cast<msg::Waypoint*>(nullptr))) want.push_back({f.name, f.idl_type});
  const auto& have = idl.at("tern_msgs::msg::MissionItem");
  CHECK_MESSAGE(have == want, "\n  IDL:        ", field_list(have), "\n  describe(): ", field_list(want));
  std::vector<Leaf> ls;
  leaves<msg::Waypoint>(ls, "", "", 0);
  msg::Waypoint base;
  for (std::size_t i = 0; i < ls.size(); ++i) assign(&base, ls[i], base_value(ls[i], i));
  for (std::size_t i = 0; i < ls.size(); ++i) {
    CAPTURE(ls[i].label);
    for (const double v : other_values(ls[i], base_value(ls[i], i))) {
      msg::Waypoint m = base;
      assign(&m, ls[i], v);
      tern_msgs::msg::MissionItem item;
      ddsi::to_mission_item(m, item);
      const msg::Waypoint back = ddsi::from_mission_item(item);
      for (const Leaf& l : ls)  // every field as sent, the changed one too
        CHECK_MESSAGE(std::memcmp(reinterpret_cast<const char*>(&back) + l.offset, reinterpret_cast<const char*>(&m) + l.offset,
                                  reflect::scalar_size(l.kind)) == 0,
                      l.label);
    }
  }
}
