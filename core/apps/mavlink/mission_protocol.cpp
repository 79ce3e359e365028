// core/apps/mavlink/mission_protocol.cpp: the mission protocol's vehicle side (mission_protocol.hpp).
#include "mavlink/mission_protocol.hpp"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <system_error>

#include "config/error.hpp"
#include "flight/host.hpp"
#include "mavlink/fence_items.hpp"
#include "mavlink/mission_items.hpp"
#include "tern/msg/mission.hpp"

namespace tern::core::mavlink {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kSamePoint = 0.01;      // m: a listed waypoint is an uploaded one within this
constexpr std::uint32_t kFilesKept = 4;  // upload files kept (the planner reads one at the tick after its edit)

msg::Waypoint listed(const path::MissionWaypoint& w) {
  msg::Waypoint out;
  out.w = w.w;
  out.type = static_cast<std::uint8_t>(w.type);  // the same order (tern/msg/path.hpp, tern/path/item.hpp)
  return out;
}

bool same(const msg::Waypoint& a, const msg::Waypoint& b) { return a.type == b.type && (a.w - b.w).norm() < kSamePoint; }

bool is_nav(const MissionItemInt& it) { return is_nav_item(it.command); }

/// The mission edit that loads `file` (a path shorter than the edit's field: write() checks).
msg::MissionEdit load_edit(std::uint32_t id, const std::filesystem::path& file) {
  msg::MissionEdit e;
  e.id = id;
  e.op = msg::MissionEdit::load_file;
  const std::string text = file.string();
  std::memcpy(e.file.data(), text.c_str(), std::min(text.size() + 1, e.file.size()));
  return e;
}

}  // namespace

MissionProtocol::MissionProtocol(Host& host, const FlightWatch& flight, Outbox out, std::uint8_t system_id, std::filesystem::path dir)
    : host_(host), flight_(flight), out_(std::move(out)), system_id_(system_id), dir_(std::move(dir)) {
  std::filesystem::create_directories(dir_);
}

MissionProtocol::~MissionProtocol() {
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);  // what is left of the uploads: nothing to do about a failure
}

bool MissionProtocol::on_frame(const Frame& f) {
  switch (f.msgid) {
    case MissionCount::kId: on_count(f); return true;
    case MissionItemInt::kId: on_item(f); return true;
    case MissionRequest::kId:
    case MissionRequestInt::kId: on_request(f); return true;
    case MissionRequestList::kId: on_list(f); return true;
    case MissionClearAll::kId: on_clear(f); return true;
    case MissionSetCurrent::kId: on_set_current(f); return true;
    case MissionAck::kId: return true;  // the end of a download: nothing kept
    default: return false;
  }
}

bool MissionProtocol::for_us(std::uint8_t sys, std::uint8_t comp) const {
  return (sys == 0 || sys == system_id_) && (comp == 0 || comp == MAV_COMP_ID_AUTOPILOT1);
}

void MissionProtocol::ack(std::uint8_t sys, std::uint8_t comp, std::uint8_t result, std::uint8_t mission_type) {
  MissionAck a;
  a.target_system = sys;
  a.target_component = comp;
  a.type = result;
  a.mission_type = mission_type;
  out_.send(MissionAck::kId, encode(a));
}

void MissionProtocol::refuse_type(const Frame& f, std::uint8_t mission_type) {
  out_.say(MAV_SEVERITY_WARNING, "mission type " + std::to_string(mission_type) + " unknown: tern takes MISSION, FENCE and RALLY");
  ack(f.sysid, f.compid, MAV_MISSION_UNSUPPORTED, mission_type);
}

bool MissionProtocol::known_type(std::uint8_t t) { return t <= MAV_MISSION_TYPE_RALLY; }

std::string MissionProtocol::type_name(std::uint8_t t) {
  return t == MAV_MISSION_TYPE_FENCE ? "geofence" : t == MAV_MISSION_TYPE_RALLY ? "rally points" : "mission";
}

void MissionProtocol::request(const Upload& u) {
  MissionRequestInt r;
  r.seq = u.next;
  r.target_system = u.gcs_sys;
  r.target_component = u.gcs_comp;
  r.mission_type = u.type;
  out_.send(MissionRequestInt::kId, encode(r));
}

void MissionProtocol::on_count(const Frame& f) {
  const auto m = decode<MissionCount>(f);
  if (!for_us(m.target_system, m.target_component)) return;
  upload_.reset();  // a new count restarts an upload
  if (!known_type(m.mission_type)) return refuse_type(f, m.mission_type);
  const std::string what = type_name(m.mission_type);
  if (m.count > kMaxItems) {
    out_.say(MAV_SEVERITY_WARNING, what + " of " + std::to_string(m.count) + " items refused: at most " + std::to_string(kMaxItems));
    return ack(f.sysid, f.compid, MAV_MISSION_NO_SPACE, m.mission_type);
  }
  if (!flight_.view().has_state) {
    out_.say(MAV_SEVERITY_WARNING, what + " refused: no position estimate yet (its origin places lat/lon)");
    return ack(f.sysid, f.compid, MAV_MISSION_DENIED, m.mission_type);
  }
  upload_ = Upload{m.count, 0, f.sysid, f.compid, m.mission_type, {}, Clock::now(), 0};
  if (m.count == 0) return finish_upload();
  request(*upload_);
}

void MissionProtocol::on_item(const Frame& f) {
  const auto it = decode<MissionItemInt>(f);
  if (!for_us(it.target_system, it.target_component) || !upload_) return;
  Upload& u = *upload_;
  if (it.mission_type != u.type) {  // one transfer at a time: an item of another list ends it
    out_.say(MAV_SEVERITY_WARNING, "mission item " + std::to_string(it.seq) + " of mission type " + std::to_string(it.mission_type) +
                                       " during a " + type_name(u.type) + " upload: the upload ends, the " + type_name(u.type) +
                                       " is unchanged");
    ack(u.gcs_sys, u.gcs_comp, MAV_MISSION_ERROR, u.type);
    upload_.reset();
    return;
  }
  if (it.seq != u.next) return request(u);  // out of order: the one expected, again
  try {
    if (u.type == MAV_MISSION_TYPE_FENCE)
      check_fence_item(it);
    else if (u.type == MAV_MISSION_TYPE_RALLY)
      check_rally_item(it);
    else
      check_item(it);
  } catch (const ItemError& e) {
    out_.say(MAV_SEVERITY_WARNING, e.what());
    ack(u.gcs_sys, u.gcs_comp, e.result(), u.type);
    upload_.reset();
    return;
  }
  u.items.push_back(it);
  u.next++;
  u.retries = 0;
  u.asked = Clock::now();
  if (u.next == u.count) return finish_upload();
  request(u);
}

void MissionProtocol::finish_upload() {
  const Upload u = std::move(*upload_);
  upload_.reset();
  if (u.type == MAV_MISSION_TYPE_MISSION) return finish_mission(u);
  const FlightView v = flight_.view();
  const GeoOrigin home(v.origin);
  try {
    if (u.type == MAV_MISSION_TYPE_FENCE) {
      std::vector<FenceZone> zones = to_zones(u.items, home);
      out_.say(MAV_SEVERITY_INFO, "geofence of " + std::to_string(zones.size()) + " zones accepted");
      host_.set_fence_zones(std::move(zones));
    } else {
      std::vector<Eigen::Vector3d> rally = to_rally(u.items, home);
      out_.say(MAV_SEVERITY_INFO, std::to_string(rally.size()) + " rally points accepted: a return goes to the nearest or home");
      host_.set_rally_points(std::move(rally));
    }
  } catch (const ItemError& e) {
    out_.say(MAV_SEVERITY_WARNING, e.what());
    return ack(u.gcs_sys, u.gcs_comp, e.result(), u.type);
  }
  kept_[u.type] = u.items;
  ack(u.gcs_sys, u.gcs_comp, MAV_MISSION_ACCEPTED, u.type);
}

void MissionProtocol::finish_mission(const Upload& u) {
  const FlightView v = flight_.view();
  const auto refuse = [&](std::uint8_t result, const std::string& why) {
    out_.say(MAV_SEVERITY_WARNING, why);
    ack(u.gcs_sys, u.gcs_comp, result);
  };
  Uploaded up;
  up.items = u.items;
  up.list_seq = v.list_seq;
  up.handed = Clock::now();
  try {
    const path::Mission m = to_mission(u.items, GeoOrigin(v.origin), &up.nav_seq);
    if (m.waypoints.size() > msg::WaypointList::kCapacity)
      return refuse(MAV_MISSION_NO_SPACE, "mission refused: " + std::to_string(m.waypoints.size()) + " nav items, more than the " +
                                              std::to_string(msg::WaypointList::kCapacity) + " of the planner's list");
    const std::string text = mission_text(m);
    for (const auto& w : path::parse_mission_text(text, "MAVLink upload").waypoints) up.waypoints.push_back(listed(w));
    up.file = write(text);
    host_.edit_mission(load_edit(next_edit_id(), up.file));  // throws ConfigError: no planner
  } catch (const ItemError& e) {
    return refuse(e.result(), e.what());
  } catch (const path::MissionError& e) {
    return refuse(MAV_MISSION_INVALID, std::string("mission refused: ") + e.what());
  } catch (const std::exception& e) {
    return refuse(MAV_MISSION_ERROR, std::string("mission refused: ") + e.what());
  }
  out_.say(MAV_SEVERITY_INFO, "mission of " + std::to_string(up.items.size()) + " items accepted: " + std::to_string(up.waypoints.size()) +
                                  " waypoints, flown once");
  const auto over_terrain = std::count_if(up.items.begin(), up.items.end(), [](const MissionItemInt& it) { return terrain(it.frame); });
  if (over_terrain > 0)
    out_.say(MAV_SEVERITY_WARNING, std::to_string(over_terrain) +
                                       " items above terrain flown above home: tern has no terrain model (flat ground at home's altitude)");
  uploaded_ = std::move(up);
  commanded_ = false;
  ack(u.gcs_sys, u.gcs_comp, MAV_MISSION_ACCEPTED);
}

std::filesystem::path MissionProtocol::write(const std::string& text) {
  const std::uint32_t n = ++files_;
  const auto name = [this](std::uint32_t k) { return dir_ / ("upload-" + std::to_string(k) + ".yaml"); };
  if (n > kFilesKept) {
    std::error_code ec;
    std::filesystem::remove(name(n - kFilesKept), ec);
  }
  const std::filesystem::path file = name(n);
  std::ofstream o(file);
  o << text;
  o.close();
  if (!o) throw std::runtime_error("cannot write " + file.string());
  if (file.string().size() >= msg::MissionEdit{}.file.size())
    throw std::runtime_error(file.string() + ": path too long for a mission edit");
  return file;
}

void MissionProtocol::on_request(const Frame& f) {
  // MISSION_REQUEST (deprecated) and MISSION_REQUEST_INT ask alike; both are answered with MISSION_ITEM_INT
  const auto answer = [&](const auto& r) {
    if (!for_us(r.target_system, r.target_component)) return;
    if (!known_type(r.mission_type)) return refuse_type(f, r.mission_type);
    const std::vector<MissionItemInt>& listed = download_[r.mission_type];
    if (r.seq >= listed.size()) return ack(f.sysid, f.compid, MAV_MISSION_INVALID_SEQUENCE, r.mission_type);
    MissionItemInt it = listed[r.seq];
    it.target_system = f.sysid;
    it.target_component = f.compid;
    it.mission_type = r.mission_type;
    out_.send(MissionItemInt::kId, encode(it));
  };
  if (f.msgid == MissionRequest::kId)
    answer(decode<MissionRequest>(f));
  else
    answer(decode<MissionRequestInt>(f));
}

void MissionProtocol::on_list(const Frame& f) {
  const auto m = decode<MissionRequestList>(f);
  if (!for_us(m.target_system, m.target_component)) return;
  if (!known_type(m.mission_type)) return refuse_type(f, m.mission_type);
  std::vector<MissionItemInt>& listed = download_[m.mission_type];
  listed = items(m.mission_type);
  MissionCount c;
  c.count = static_cast<std::uint16_t>(listed.size());
  c.target_system = f.sysid;
  c.target_component = f.compid;
  c.mission_type = m.mission_type;
  out_.send(MissionCount::kId, encode(c));
}

void MissionProtocol::on_clear(const Frame& f) {
  const auto m = decode<MissionClearAll>(f);
  if (!for_us(m.target_system, m.target_component)) return;
  if (!known_type(m.mission_type) && m.mission_type != MAV_MISSION_TYPE_ALL) return refuse_type(f, m.mission_type);
  upload_.reset();
  const bool all = m.mission_type == MAV_MISSION_TYPE_ALL;
  if (all || m.mission_type == MAV_MISSION_TYPE_FENCE) {
    host_.set_fence_zones({});
    kept_[MAV_MISSION_TYPE_FENCE] = std::vector<MissionItemInt>{};
  }
  if (all || m.mission_type == MAV_MISSION_TYPE_RALLY) {
    host_.set_rally_points({});
    kept_[MAV_MISSION_TYPE_RALLY] = std::vector<MissionItemInt>{};
  }
  if (!all && m.mission_type != MAV_MISSION_TYPE_MISSION) return ack(f.sysid, f.compid, MAV_MISSION_ACCEPTED, m.mission_type);
  msg::MissionEdit e;
  e.id = next_edit_id();
  e.op = msg::MissionEdit::clear;
  try {
    host_.edit_mission(e);
  } catch (const std::exception& err) {
    out_.say(MAV_SEVERITY_WARNING, std::string("mission not cleared: ") + err.what());
    return ack(f.sysid, f.compid, MAV_MISSION_ERROR, m.mission_type);
  }
  Uploaded none;
  none.list_seq = flight_.view().list_seq;
  none.handed = Clock::now();
  uploaded_ = std::move(none);
  commanded_ = false;
  ack(f.sysid, f.compid, MAV_MISSION_ACCEPTED, m.mission_type);
}

void MissionProtocol::on_set_current(const Frame& f) {
  const auto m = decode<MissionSetCurrent>(f);
  if (!for_us(m.target_system, m.target_component)) return;
  const std::string why = fly_from(m.seq);
  if (!why.empty()) out_.say(MAV_SEVERITY_WARNING, "MISSION_SET_CURRENT " + std::to_string(m.seq) + " refused: " + why);
}

void MissionProtocol::on_tick() {
  if (!upload_ || Clock::now() - upload_->asked < kRetryPeriod) return;
  Upload& u = *upload_;
  if (u.retries >= kRetries) {
    out_.say(MAV_SEVERITY_WARNING, type_name(u.type) + " upload given up: item " + std::to_string(u.next) + " not received after " +
                                       std::to_string(kRetries + 1) + " requests; the " + type_name(u.type) + " is unchanged");
    ack(u.gcs_sys, u.gcs_comp, MAV_MISSION_OPERATION_CANCELLED, u.type);
    upload_.reset();
    return;
  }
  u.retries++;
  u.asked = Clock::now();
  request(u);
}

bool MissionProtocol::ours_flown(const FlightView& v) const {
  if (v.list_seq == uploaded_->list_seq || !v.list) return true;  // handed over, not yet listed by the planner
  const msg::WaypointList& p = *v.list;
  bool ours = true;
  if (p.count == 0 || p.count > uploaded_->waypoints.size())
    ours = p.count == 0 && uploaded_->waypoints.empty();
  else
    for (std::uint32_t i = 0; i < p.count && ours; ++i)
      ours = std::any_of(uploaded_->waypoints.begin(), uploaded_->waypoints.end(),
                         [&](const msg::Waypoint& w) { return same(w, p.items[i]); });
  if (ours) uploaded_->listed = true;
  // a list the planner published before it applied the edit (its old mission, republished)
  // (not after a command replaced it: then the list is the command's)
  return ours || (!uploaded_->listed && !commanded_ && Clock::now() - uploaded_->handed < kHandover);
}

std::vector<MissionItemInt> MissionProtocol::items(std::uint8_t mission_type) const {
  if (mission_type == MAV_MISSION_TYPE_MISSION) return items();
  if (kept_[mission_type]) return *kept_[mission_type];
  const FlightView v = flight_.view();
  if (!v.has_state) return {};
  const auto g = host_.fence_geometry();  // the config's
  const GeoOrigin home(v.origin);
  return mission_type == MAV_MISSION_TYPE_FENCE ? fence_items(g.zones, home) : rally_items(g.rally, home);
}

std::vector<MissionItemInt> MissionProtocol::items() const {
  const FlightView v = flight_.view();
  if (uploaded_ && ours_flown(v)) return uploaded_->items;
  if (v.list && v.has_state) return to_items(*v.list, GeoOrigin(v.origin));
  return {};
}

std::optional<std::uint16_t> MissionProtocol::current_seq() const {
  const FlightView v = flight_.view();
  if (!v.list || v.waypoint_index < 0 || static_cast<std::uint32_t>(v.waypoint_index) >= v.list->count) return std::nullopt;
  const msg::Waypoint& flown = v.list->items[static_cast<std::size_t>(v.waypoint_index)];
  if (uploaded_ && ours_flown(v)) {
    for (std::size_t k = 0; k < uploaded_->waypoints.size(); ++k)
      if (same(uploaded_->waypoints[k], flown)) return uploaded_->nav_seq[k];
    return std::nullopt;
  }
  if (!v.has_state) return std::nullopt;
  std::int32_t nav = -1;
  for (const MissionItemInt& it : to_items(*v.list, GeoOrigin(v.origin)))
    if (is_nav(it) && ++nav == v.waypoint_index) return it.seq;
  return std::nullopt;
}

void MissionProtocol::keep_mission() {
  const FlightView v = flight_.view();
  const bool keep = !(uploaded_ && (ours_flown(v) || commanded_)) && v.list && v.list->count > 0 && v.has_state;
  commanded_ = true;  // the list flown next is a command's: a second command keeps the mission kept now
  if (!keep) return;
  Uploaded kept;
  kept.items = to_items(*v.list, GeoOrigin(v.origin));
  for (const MissionItemInt& it : kept.items)
    if (is_nav(it)) kept.nav_seq.push_back(it.seq);
  for (std::uint32_t i = 0; i < v.list->count; ++i) kept.waypoints.push_back(v.list->items[i]);
  kept.list_seq = v.list_seq;
  kept.listed = true;  // the list flown now
  try {
    kept.file = write(mission_text(to_mission(*v.list)));
  } catch (const std::exception& e) {
    out_.say(MAV_SEVERITY_WARNING, std::string("the mission is not kept for MISSION_START: ") + e.what());
    return;
  }
  uploaded_ = std::move(kept);
}

std::string MissionProtocol::fly_from(std::uint16_t seq) {
  const FlightView v = flight_.view();
  const bool kept = uploaded_ && !uploaded_->file.empty();  // an upload, or the mission kept by a command
  const std::vector<MissionItemInt> all = kept ? uploaded_->items : items();
  if (seq >= all.size()) return "no item " + std::to_string(seq) + " (the mission has " + std::to_string(all.size()) + ")";
  const auto first_nav = std::find_if(all.begin() + seq, all.end(), is_nav);
  if (first_nav == all.end()) return "no nav item from item " + std::to_string(seq);
  const auto index = static_cast<std::uint32_t>(std::count_if(all.begin(), first_nav, is_nav));
  try {
    if (kept) {  // loaded again: the planner's list may be renumbered (set_current) or replaced (a command)
      host_.edit_mission(load_edit(next_edit_id(), uploaded_->file));
      uploaded_->list_seq = v.list_seq;
      uploaded_->handed = Clock::now();
      uploaded_->listed = false;
    }
    msg::MissionEdit e;
    e.id = next_edit_id();
    e.op = msg::MissionEdit::set_current;
    e.index = index;
    host_.edit_mission(e);
  } catch (const std::exception& err) {
    return err.what();
  }
  commanded_ = false;
  return "";
}

}  // namespace tern::core::mavlink
