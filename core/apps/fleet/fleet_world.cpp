// The fleet's view of its world between ticks: positions in one frame, the separation monitor
// and its response, and the run's documents (fleet.json, summary.json).
#include <algorithm>
#include <fstream>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "fleet/fleet.hpp"
#include "tern/msg/all.hpp"

namespace tern::core {

namespace {

const msg::State* state_of(const Host& host, const std::string& topic) {
  const OutputBase* out = host.topic_source(topic);
  if (out == nullptr || out->sequence() == 0 || out->type().fingerprint != reflect::fingerprint<msg::State>()) return nullptr;
  return static_cast<const msg::State*>(out->data());
}

}  // namespace

// The simulator's truth is in the world's frame (every vehicle's simulator has the world's
// origin, fleet_config.hpp), which is then the common frame.
std::optional<Eigen::Vector3d> Fleet::true_position(const Vehicle& v) {
  const msg::State* s = state_of(*v.host, "truth");
  if (s == nullptr) return std::nullopt;
  if (!common_ && s->origin_valid) common_.emplace(s->origin_lat, s->origin_lon, s->origin_alt);
  return Eigen::Vector3d(s->p_n, s->p_e, s->p_d);
}

// The estimate is in the vehicle's own frame (its origin: its first GNSS fix): moved into the
// common frame by its origin's offset, recomputed when the origin changes. The frames' axes
// differ by the angle between the origins' verticals (1e-4 rad per 640 m apart): centimetres
// over the few kilometres of a team's area.
std::optional<Eigen::Vector3d> Fleet::estimated_position(Vehicle& v) {
  const msg::State* s = state_of(*v.host, "state");
  if (s == nullptr || !s->origin_valid) return std::nullopt;
  if (!common_) common_.emplace(s->origin_lat, s->origin_lon, s->origin_alt);  // no simulator: the first vehicle's origin
  const GeoPoint o{s->origin_lat, s->origin_lon, s->origin_alt};
  if (!v.origin_seen || v.origin_seen->lat != o.lat || v.origin_seen->lon != o.lon || v.origin_seen->alt != o.alt) {
    v.origin_seen = o;
    v.origin_offset = common_->to_ned(o);
  }
  return v.origin_offset + Eigen::Vector3d(s->p_n, s->p_e, s->p_d);
}

std::vector<Fleet::Track> Fleet::others_seen_from(std::size_t focus) {
  std::vector<Track> out;
  const auto self = estimated_position(vehicles_[focus]);
  if (!self) return out;
  for (std::size_t i = 0; i < vehicles_.size(); ++i) {
    if (i == focus) continue;
    const auto p = estimated_position(vehicles_[i]);
    const msg::State* s = state_of(*vehicles_[i].host, "state");
    if (p && s) out.push_back({vehicles_[i].name, *p - vehicles_[focus].origin_offset, s->psi});
  }
  return out;
}

void Fleet::watch_separation(Nanos now) {
  SeparationMonitor::Positions est(vehicles_.size()), truth(vehicles_.size());
  for (std::size_t i = 0; i < vehicles_.size(); ++i) {
    if (!vehicles_[i].active) continue;  // landed, crashed or ended: out of the air traffic
    truth[i] = true_position(vehicles_[i]);
    est[i] = estimated_position(vehicles_[i]);
  }
  for (const auto& [a, b] : separation_->observe(now, est, truth)) {
    log_->warn("t={:.3f} s: separation: {} and {} {:.1f} m apart (estimated), closer than {} m", to_seconds(now), vehicles_[a].name,
               vehicles_[b].name, (*est[a] - *est[b]).norm(), config_.separation.min_distance);
    if (config_.separation.response == SeparationConfig::Response::hold) hold(b, now);
  }
}

// The `hold` response: the vehicle orbits over where it estimates it is, hold_climb higher (a
// mission edit its path planner applies next tick, as an operator's would be).
void Fleet::hold(std::size_t i, Nanos now) {
  Vehicle& v = vehicles_[i];
  const msg::State* s = state_of(*v.host, "state");
  if (s == nullptr || !v.host->takes_mission_edits()) {
    log_->warn("t={:.3f} s: separation: {} cannot be sent a hold (no state or no path planner)", to_seconds(now), v.name);
    return;
  }
  msg::MissionEdit e;
  e.stamp = now;
  e.op = msg::MissionEdit::add;
  e.set_current_wp = true;
  e.waypoint.type = msg::Waypoint::loiter;
  e.waypoint.w = Eigen::Vector3d(s->p_n, s->p_e, s->p_d - config_.separation.hold_climb);
  e.waypoint.Va_d = s->Va > 1.0 ? s->Va : 0.0;
  v.host->edit_mission(e, /*own=*/true);  // a safety hold: never refused
  log_->warn("t={:.3f} s: separation: {} holds over ({:.0f}, {:.0f}) {:.0f} m higher", to_seconds(now), v.name, s->p_n, s->p_e,
             config_.separation.hold_climb);
}

nlohmann::ordered_json Fleet::summary(const FleetResult& r) const {
  nlohmann::ordered_json vehicles = nlohmann::ordered_json::object();
  for (const auto& [name, f] : r.vehicles)
    vehicles[name] = {{"end_reason", f.end_reason}, {"ok", f.ok}, {"flown_s", to_seconds(f.flown)}, {"log", name}};
  // the flight's end as one word for tools that read one flight's summary (tern campaign): the
  // vehicles' common end reason, else theirs joined ("duration,plugin_failed")
  std::set<std::string> ends;
  double flown = 0;
  for (const auto& [name, f] : r.vehicles) {
    ends.insert(f.end_reason);
    flown = std::max(flown, to_seconds(f.flown));
  }
  nlohmann::ordered_json out = {{"mission", config_.name},
                                {"seed", seed_},
                                {"end_reason", fmt::format("{}", fmt::join(ends, ","))},
                                {"duration_s", flown},
                                {"vehicles", vehicles}};
  out["separation"] = separation_->report();
  if (r.coordination) {
    nlohmann::ordered_json c = {{"end_reason", r.coordination->end_reason}, {"ok", r.coordination->ok}, {"log", "coordination"}};
    std::ifstream in(r.coordination->run_dir / "summary.json");
    if (in) {
      const auto s = nlohmann::ordered_json::parse(in, nullptr, false);
      if (s.is_object() && s.contains("instances")) c["instances"] = s["instances"];  // each plugin's summary() figures
    }
    out["coordination"] = c;
  }
  out["ok"] = r.ok();
  return out;
}

void Fleet::write_documents(const FleetResult& r) const {
  nlohmann::ordered_json names = nlohmann::ordered_json::array();
  for (const auto& v : vehicles_) names.push_back(v.name);
  const nlohmann::ordered_json fleet = {
      {"mission", config_.name}, {"config", config_.file.string()},          {"seed", seed_},
      {"vehicles", names},       {"coordination", coordination_ != nullptr}, {"format", "tern fleet run 1"}};
  // wall-clock figures apart from summary.json (which is the same bytes for the same flight)
  double vehicle_s = 0;
  for (const auto& [name, f] : r.vehicles) vehicle_s += to_seconds(f.flown);
  const double flight_s = r.summary.value("duration_s", 0.0);
  const nlohmann::ordered_json timing = {{"wall_s", r.wall_s},
                                         {"real_time_factor", r.wall_s > 0 ? flight_s / r.wall_s : 0.0},
                                         {"vehicle_seconds_per_wall_s", r.wall_s > 0 ? vehicle_s / r.wall_s : 0.0}};
  for (const auto& [file, doc] : {std::pair<const char*, const nlohmann::ordered_json*>{"fleet.json", &fleet},
                                  {"summary.json", &r.summary},
                                  {"timing.json", &timing}}) {
    const fs::path tmp = run_dir_ / (std::string(file) + ".tmp");
    std::ofstream out(tmp);
    out << doc->dump(2) << "\n";
    out.close();
    std::error_code ec;
    if (out) fs::rename(tmp, run_dir_ / file, ec);
    if (!out || ec) log_->error("{}: cannot write {}", run_dir_.string(), file);
  }
}

}  // namespace tern::core
