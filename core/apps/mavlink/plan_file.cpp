// core/apps/mavlink/plan_file.cpp: QGroundControl's .plan files <-> MAVLink items (plan_file.hpp).
#include "mavlink/plan_file.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "mavlink/mission_items.hpp"

namespace tern::core::mavlink {
namespace {

using json = nlohmann::json;
constexpr double kE7 = 1e7;  // degE7 per degree

/// Where in the file a value is, for the one error line.
struct Field {
  const std::string& source;
  std::string path;
  Field operator/(const std::string& key) const { return {source, path.empty() ? key : path + "." + key}; }
  Field operator[](std::size_t i) const { return {source, path + "[" + std::to_string(i) + "]"}; }
  [[noreturn]] void fail(const std::string& why) const { throw PlanError(source + ": " + path + ": " + why); }
};

std::string shown(const json& v) {
  std::string s = v.dump();
  return s.size() > 40 ? s.substr(0, 40) + "..." : s;
}

const json& member(const json& obj, const char* key, const Field& f) {
  if (!obj.is_object()) f.fail("expected an object, got " + shown(obj));
  const auto it = obj.find(key);
  if (it == obj.end()) (f / key).fail("missing");
  return *it;
}

const json* optional_member(const json& obj, const char* key) {
  const auto it = obj.find(key);
  return it == obj.end() || it->is_null() ? nullptr : &*it;
}

const json& array(const json& v, const Field& f) {
  if (!v.is_array()) f.fail("expected a list, got " + shown(v));
  return v;
}

/// A number; null is NaN where `nullable` (QGroundControl writes NaN parameters as null).
double number(const json& v, const Field& f, bool nullable = false) {
  if (v.is_number()) return v.get<double>();
  if (nullable && v.is_null()) return std::nan("");
  f.fail(std::string("expected a number") + (nullable ? " or null" : "") + ", got " + shown(v));
}

bool boolean(const json& obj, const char* key, bool otherwise, const Field& f) {
  const json* v = optional_member(obj, key);
  if (!v) return otherwise;
  if (!v->is_boolean()) (f / key).fail("expected true or false, got " + shown(*v));
  return v->get<bool>();
}

std::int32_t degE7(double deg, const Field& f) {
  if (!(std::fabs(deg) <= 360.0)) f.fail("expected degrees, got " + std::to_string(deg));
  return static_cast<std::int32_t>(std::llround(deg * kE7));
}

/// [lat, lon, alt] (n = 3), or [lat, lon] with an optional alt (n = 2; absent: 0).
Eigen::Vector3d coordinate(const json& v, const Field& f, std::size_t n) {
  array(v, f);
  if (v.size() < 2 || v.size() > 3 || (n == 3 && v.size() != 3)) f.fail("expected [lat, lon" + std::string(n == 3 ? ", alt]" : "]"));
  return {number(v[0], f[0]), number(v[1], f[1]), v.size() == 3 ? number(v[2], f[2]) : 0.0};
}

MissionItemInt item(std::uint16_t command, std::uint8_t frame, std::uint8_t type) {
  MissionItemInt it;
  it.command = command;
  it.frame = frame;
  it.autocontinue = 1;
  it.mission_type = type;
  return it;
}

bool global(std::uint8_t frame) { return frame != MAV_FRAME_MISSION; }

/// param5 or param6 of an item without a position (MISSION_ITEM_INT carries them as int32): NaN is 0.
std::int32_t int32_param(double v, const Field& f) {
  if (!std::isfinite(v)) return 0;
  if (!(v >= -2147483648.0 && v <= 2147483647.0)) f.fail(item_number(v) + ": MISSION_ITEM_INT carries this parameter as an int32");
  return static_cast<std::int32_t>(v);
}

/// Numbers items 0.. as MISSION_ITEM_INT's uint16 seq does; more than it holds: one line.
void number_items(std::vector<MissionItemInt>& items, const Field& f) {
  if (items.size() > 65535) f.fail(std::to_string(items.size()) + " items: a MAVLink list holds at most 65535");
  for (std::size_t k = 0; k < items.size(); ++k) items[k].seq = static_cast<std::uint16_t>(k);
}

/// A SimpleItem: command, frame, params[7] (null: NaN), autoContinue.
MissionItemInt simple_item(const json& j, const Field& f) {
  const double command = number(member(j, "command", f), f / "command");
  const double frame = number(member(j, "frame", f), f / "frame");
  if (!(command >= 0 && command <= 65535 && std::floor(command) == command)) (f / "command").fail("not a MAV_CMD: " + shown(j["command"]));
  if (!(frame >= 0 && frame <= 255 && std::floor(frame) == frame)) (f / "frame").fail("not a MAV_FRAME: " + shown(j["frame"]));
  MissionItemInt it = item(static_cast<std::uint16_t>(command), static_cast<std::uint8_t>(frame), MAV_MISSION_TYPE_MISSION);
  const json& params = array(member(j, "params", f), f / "params");
  if (params.size() != 7) (f / "params").fail("expected 7 parameters, got " + std::to_string(params.size()));
  double p[7];
  for (std::size_t i = 0; i < 7; ++i) p[i] = number(params[i], (f / "params")[i], true);
  it.param1 = static_cast<float>(p[0]), it.param2 = static_cast<float>(p[1]);
  it.param3 = static_cast<float>(p[2]), it.param4 = static_cast<float>(p[3]);
  const bool has_position = global(it.frame) && std::isfinite(p[4]) && std::isfinite(p[5]);
  it.x = has_position ? degE7(p[4], (f / "params")[4]) : int32_param(p[4], (f / "params")[4]);
  it.y = has_position ? degE7(p[5], (f / "params")[5]) : int32_param(p[5], (f / "params")[5]);
  it.z = static_cast<float>(p[6]);
  it.autocontinue = boolean(j, "autoContinue", true, f) ? 1 : 0;
  return it;
}

/// An item's doJumpId: a whole number >= 0 (QGroundControl numbers its items from 1).
long jump_id(const json& v, const Field& f) {
  const double id = number(v, f);
  if (!(id >= 0.0 && id < 2147483648.0 && std::floor(id) == id)) f.fail("expected a whole number >= 0, got " + shown(v));
  return static_cast<long>(id);
}

/// QGroundControl's fixed-wing landing pattern, as it uploads it: DO_LAND_START, a loiter down to
/// the approach altitude (NAV_LOITER_TO_ALT, or a NAV_WAYPOINT without useLoiterToAlt), NAV_LAND.
std::vector<MissionItemInt> landing_pattern(const json& j, const Field& f) {
  const char* approach_key = j.contains("landingApproachCoordinate") ? "landingApproachCoordinate" : "loiterCoordinate";
  const Eigen::Vector3d land = coordinate(member(j, "landCoordinate", f), f / "landCoordinate", 3);
  const Eigen::Vector3d approach = coordinate(member(j, approach_key, f), f / approach_key, 3);
  const std::uint8_t frame = boolean(j, "altitudesAreRelative", true, f) ? MAV_FRAME_GLOBAL_RELATIVE_ALT : MAV_FRAME_GLOBAL;
  const double radius = j.contains("loiterRadius") ? number(j["loiterRadius"], f / "loiterRadius") : 0.0;
  MissionItemInt start = item(MAV_CMD_DO_LAND_START, frame, MAV_MISSION_TYPE_MISSION);
  start.x = degE7(land.x(), f / "landCoordinate"), start.y = degE7(land.y(), f / "landCoordinate");
  const bool loiter = boolean(j, "useLoiterToAlt", true, f);
  MissionItemInt down = item(loiter ? MAV_CMD_NAV_LOITER_TO_ALT : MAV_CMD_NAV_WAYPOINT, frame, MAV_MISSION_TYPE_MISSION);
  if (loiter) down.param2 = static_cast<float>(boolean(j, "loiterClockwise", true, f) ? radius : -radius);
  down.x = degE7(approach.x(), f / approach_key), down.y = degE7(approach.y(), f / approach_key);
  down.z = static_cast<float>(approach.z());
  MissionItemInt touchdown = item(MAV_CMD_NAV_LAND, frame, MAV_MISSION_TYPE_MISSION);
  touchdown.param4 = std::nanf("");  // the heading: the course from the approach point
  touchdown.x = start.x, touchdown.y = start.y;
  touchdown.z = static_cast<float>(land.z());
  return {start, down, touchdown};
}

/// A ComplexItem's MISSION items: a survey's or corridor scan's generated Items, or a landing pattern.
std::vector<MissionItemInt> complex_items(const json& j, const Field& f, std::map<long, std::size_t>& jump_ids, std::size_t next_seq) {
  const json& type = member(j, "complexItemType", f);
  if (type == "fwLandingPattern") return landing_pattern(j, f);
  const json* transect = optional_member(j, "TransectStyleComplexItem");
  if (!transect) (f / "complexItemType").fail(shown(type) + ": tern reads surveys, corridor scans and fwLandingPattern");
  const Field items_field = f / "TransectStyleComplexItem" / "Items";
  const json& items = array(member(*transect, "Items", f / "TransectStyleComplexItem"), items_field);
  std::vector<MissionItemInt> out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    out.push_back(simple_item(items[i], items_field[i]));
    if (const json* id = optional_member(items[i], "doJumpId")) jump_ids[jump_id(*id, items_field[i] / "doJumpId")] = next_seq + i;
  }
  return out;
}

/// DO_JUMP's param1 in a plan is its target's doJumpId; on the wire it is the target's seq.
void resolve_jumps(std::vector<MissionItemInt>& items, const std::map<long, std::size_t>& jump_ids, const Field& f) {
  for (MissionItemInt& it : items) {
    if (it.command != MAV_CMD_DO_JUMP) continue;
    const bool whole = it.param1 >= 0.0f && it.param1 < 2147483648.0f && std::floor(it.param1) == it.param1;
    const auto target = whole ? jump_ids.find(static_cast<long>(it.param1)) : jump_ids.end();
    if (target == jump_ids.end())
      (f / "items").fail("DO_JUMP (item " + std::to_string(it.seq) + ") to doJumpId " + std::to_string(it.param1) + ": no item has it");
    it.param1 = static_cast<float>(target->second);
  }
}

std::vector<MissionItemInt> mission_items(const json& mission, const Field& f) {
  const json& items = array(member(mission, "items", f), f / "items");
  std::vector<MissionItemInt> out;
  std::map<long, std::size_t> jump_ids;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Field fi = (f / "items")[i];
    const json& type = member(items[i], "type", fi);
    if (type == "SimpleItem") {
      if (const json* id = optional_member(items[i], "doJumpId")) jump_ids[jump_id(*id, fi / "doJumpId")] = out.size();
      out.push_back(simple_item(items[i], fi));
    } else if (type == "ComplexItem") {
      for (const MissionItemInt& it : complex_items(items[i], fi, jump_ids, out.size())) out.push_back(it);
    } else {
      (fi / "type").fail(shown(type) + ": expected \"SimpleItem\" or \"ComplexItem\"");
    }
  }
  number_items(out, f / "items");
  resolve_jumps(out, jump_ids, f);
  return out;
}

std::vector<MissionItemInt> fence_items_of(const json& fence, const Field& f) {
  std::vector<MissionItemInt> out;
  if (const json* polygons = optional_member(fence, "polygons")) {
    for (std::size_t i = 0; i < array(*polygons, f / "polygons").size(); ++i) {
      const Field fp = (f / "polygons")[i];
      const bool inclusion = boolean((*polygons)[i], "inclusion", true, fp);
      const json& vertices = array(member((*polygons)[i], "polygon", fp), fp / "polygon");
      for (std::size_t v = 0; v < vertices.size(); ++v) {
        const Eigen::Vector3d c = coordinate(vertices[v], (fp / "polygon")[v], 2);
        MissionItemInt it = item(inclusion ? MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION : MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION,
                                 MAV_FRAME_GLOBAL_RELATIVE_ALT, MAV_MISSION_TYPE_FENCE);
        it.param1 = static_cast<float>(vertices.size());
        it.x = degE7(c.x(), (fp / "polygon")[v]), it.y = degE7(c.y(), (fp / "polygon")[v]);
        out.push_back(it);
      }
    }
  }
  if (const json* circles = optional_member(fence, "circles")) {
    for (std::size_t i = 0; i < array(*circles, f / "circles").size(); ++i) {
      const Field fc = (f / "circles")[i];
      const json& circle = member((*circles)[i], "circle", fc);
      const Eigen::Vector3d c = coordinate(member(circle, "center", fc / "circle"), fc / "circle" / "center", 2);
      MissionItemInt it =
          item(boolean((*circles)[i], "inclusion", true, fc) ? MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION : MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION,
               MAV_FRAME_GLOBAL_RELATIVE_ALT, MAV_MISSION_TYPE_FENCE);
      it.param1 = static_cast<float>(number(member(circle, "radius", fc / "circle"), fc / "circle" / "radius"));
      it.x = degE7(c.x(), fc / "circle" / "center"), it.y = degE7(c.y(), fc / "circle" / "center");
      out.push_back(it);
    }
  }
  number_items(out, f);
  return out;
}

std::vector<MissionItemInt> rally_items_of(const json& rally, const Field& f) {
  std::vector<MissionItemInt> out;
  const json* points = optional_member(rally, "points");
  if (!points) return out;
  for (std::size_t i = 0; i < array(*points, f / "points").size(); ++i) {
    const Field fp = (f / "points")[i];
    const Eigen::Vector3d c = coordinate((*points)[i], fp, 3);
    MissionItemInt it = item(MAV_CMD_NAV_RALLY_POINT, MAV_FRAME_GLOBAL_RELATIVE_ALT, MAV_MISSION_TYPE_RALLY);
    it.x = degE7(c.x(), fp), it.y = degE7(c.y(), fp);
    it.z = static_cast<float>(c.z());
    out.push_back(it);
  }
  number_items(out, f / "points");
  return out;
}

}  // namespace

Plan parse_plan(const std::string& text, const std::string& source) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {  // a syntax error, or a number past a double (out_of_range 406)
    throw PlanError(source + ": not JSON (" + std::string(e.what()).substr(0, 120) + ")");
  }
  const Field top{source, ""};
  const json* file_type = root.is_object() ? optional_member(root, "fileType") : nullptr;
  if (!file_type || *file_type != "Plan")
    throw PlanError(source + ": fileType: not a QGroundControl plan (expected \"fileType\": \"Plan\")");
  Plan plan;
  const json& mission = member(root, "mission", top);
  const Eigen::Vector3d home =
      coordinate(member(mission, "plannedHomePosition", top / "mission"), top / "mission" / "plannedHomePosition", 3);
  if (std::fabs(home.x()) > 90.0 || std::fabs(home.y()) > 180.0)
    (top / "mission" / "plannedHomePosition").fail("latitude in [-90, 90], longitude in [-180, 180] expected");
  plan.home = GeoPoint{home.x(), home.y(), home.z()};
  if (const json* cruise = optional_member(mission, "cruiseSpeed")) plan.cruise_speed = number(*cruise, top / "mission" / "cruiseSpeed");
  plan.mission = mission_items(mission, top / "mission");
  if (const json* fence = optional_member(root, "geoFence")) plan.fence = fence_items_of(*fence, top / "geoFence");
  if (const json* rally = optional_member(root, "rallyPoints")) plan.rally = rally_items_of(*rally, top / "rallyPoints");
  return plan;
}

Plan read_plan(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw PlanError(file.string() + ": not a file");
  const auto size = std::filesystem::file_size(file, ec);
  if (ec || size > kMaxPlanBytes)
    throw PlanError(file.string() + ": " +
                    (ec ? ec.message() : std::to_string(size) + " bytes, more than a plan holds (" + std::to_string(kMaxPlanBytes) + ")"));
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw PlanError(file.string() + ": cannot be read");
  return parse_plan(text.str(), file.string());
}

namespace {

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json simple_json(const MissionItemInt& it) {
  const bool positioned = global(it.frame);
  const double x = positioned ? it.x / kE7 : it.x, y = positioned ? it.y / kE7 : it.y;
  double p1 = it.param1;
  if (it.command == MAV_CMD_DO_JUMP) p1 = it.param1 + 1.0;  // doJumpId = seq + 1 (below)
  return {{"type", "SimpleItem"},
          {"command", it.command},
          {"frame", it.frame},
          {"autoContinue", it.autocontinue != 0},
          {"doJumpId", it.seq + 1},
          {"params", json::array({number_or_null(p1), number_or_null(it.param2), number_or_null(it.param3), number_or_null(it.param4), x, y,
                                  number_or_null(it.z)})}};
}

json fence_json(const std::vector<MissionItemInt>& fence) {
  json polygons = json::array(), circles = json::array();
  for (std::size_t i = 0; i < fence.size(); ++i) {
    const MissionItemInt& it = fence[i];
    const bool circle = it.command == MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION || it.command == MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION;
    if (circle) {
      circles.push_back({{"inclusion", it.command == MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION},
                         {"circle", {{"center", {it.x / kE7, it.y / kE7}}, {"radius", it.param1}}},
                         {"version", 1}});
      continue;
    }
    json vertices = json::array();
    // param1: the polygon's vertex count (fence_items writes it; anything else: this vertex alone)
    const std::size_t n = it.param1 >= 1.0f && it.param1 <= static_cast<float>(fence.size() - i) ? static_cast<std::size_t>(it.param1) : 1;
    for (std::size_t k = i; k < i + n && k < fence.size(); ++k) vertices.push_back({fence[k].x / kE7, fence[k].y / kE7});
    polygons.push_back({{"inclusion", it.command == MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION}, {"polygon", vertices}, {"version", 1}});
    i += n > 0 ? n - 1 : 0;
  }
  return {{"circles", circles}, {"polygons", polygons}, {"version", 2}};
}

}  // namespace

std::string plan_json(const Plan& plan) {
  json items = json::array(), rally = json::array();
  for (const MissionItemInt& it : plan.mission) items.push_back(simple_json(it));
  for (const MissionItemInt& it : plan.rally) rally.push_back({it.x / kE7, it.y / kE7, it.z});
  const json root = {{"fileType", "Plan"},
                     {"version", 1},
                     {"groundStation", "tern"},
                     {"mission",
                      {{"version", 2},
                       {"firmwareType", 0},  // MAV_AUTOPILOT_GENERIC
                       {"vehicleType", 1},   // MAV_TYPE_FIXED_WING
                       {"cruiseSpeed", plan.cruise_speed},
                       {"items", items},
                       {"plannedHomePosition", {plan.home.lat, plan.home.lon, plan.home.alt}}}},
                     {"geoFence", fence_json(plan.fence)},
                     {"rallyPoints", {{"points", rally}, {"version", 2}}}};
  return root.dump(4) + "\n";
}

}  // namespace tern::core::mavlink
