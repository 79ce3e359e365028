#include "console/telemetry.hpp"

#include <cmath>

#include "flight/host.hpp"

namespace tern::core {
namespace {

/// JSON has no NaN or infinity: a non-finite value is sent as null (the chart shows a gap).
nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json ned(const Eigen::Vector3d& v) { return {num(v.x()), num(v.y()), num(v.z())}; }

}  // namespace

std::function<void(Nanos)> TelemetryTap::observer(const Host& host) {
  topics_ = TopicTap(period_);
  return [this, &host](Nanos now) {
    if (topics_.take(host, now)) take(host);
  };
}

void TelemetryTap::take(const Host& host) {
  Snapshot& s = staging_;
  static_cast<FlightTopics&>(s) = topics_.topics();
  const auto& h = host.handovers();
  s.handovers = h.size();
  s.active = h.empty() ? "" : h.back().to;
  if (h.empty() && s.has_phase) {  // no handover yet: the phase table's controller
    const auto& table = host.config().phases;
    const auto it = table.find(s.phase.phase);
    s.active = it == table.end() ? "" : it->second;
  }
  s.handover_reason = h.empty() ? "" : h.back().reason;
  if (traffic_) s.traffic = traffic_();
  std::lock_guard lk(mu_);
  s.seq = latest_.seq + 1;
  latest_ = s;
}

Snapshot TelemetryTap::latest() const {
  std::lock_guard lk(mu_);
  return latest_;
}

nlohmann::json to_json(const Snapshot& s, bool with_waypoints) {
  nlohmann::json j = {{"type", "telemetry"}, {"t", to_seconds(s.t)}};
  if (s.has_state) {
    const auto& x = s.state;
    j["state"] = {{"p_n", num(x.p_n)},     {"p_e", num(x.p_e)}, {"h", num(-x.p_d)},  {"phi", num(x.phi)},
                  {"theta", num(x.theta)}, {"psi", num(x.psi)}, {"chi", num(x.chi)}, {"Va", num(x.Va)},
                  {"Vg", num(x.Vg)},       {"valid", x.valid},  {"p_d", num(x.p_d)}, {"w", {num(x.w_n), num(x.w_e), num(x.w_d)}}};
  }
  if (s.has_command) j["command"] = {{"Va_c", num(s.command.Va_c)}, {"h_c", num(s.command.h_c)}, {"chi_c", num(s.command.chi_c)}};
  if (s.has_internals) j["internals"] = {{"phi_c", num(s.internals.phi_c)}, {"theta_c", num(s.internals.theta_c)}};
  if (s.has_actuators) {
    const auto& a = s.actuators;
    j["actuators"] = {{"delta_a", num(a.delta_a)}, {"delta_e", num(a.delta_e)}, {"delta_r", num(a.delta_r)}, {"delta_t", num(a.delta_t)}};
  }
  if (s.has_phase) j["phase"] = std::string(msg::phase_name(s.phase.phase));
  if (s.has_path) {
    const auto& p = s.path;
    j["path"] = {{"type", p.path_type == msg::CurrentPath::orbit ? "orbit" : "line"},
                 {"r", ned(p.r)},
                 {"q", ned(p.q)},
                 {"c", ned(p.c)},
                 {"rho", num(p.rho)},
                 {"lambda", p.lambda},
                 {"waypoint", p.waypoint_index}};
  }
  if (s.has_rc) j["rc"] = {{"override", s.rc.rc_override}, {"failsafe", s.rc.failsafe}};
  j["safety"] = {{"handovers", s.handovers}, {"active", s.active}, {"reason", s.handover_reason}};
  if (!s.traffic.empty()) {
    nlohmann::json t = nlohmann::json::array();
    for (const auto& v : s.traffic)
      t.push_back({{"name", v.name}, {"p_n", num(v.p_n)}, {"p_e", num(v.p_e)}, {"h", num(v.h)}, {"psi", num(v.psi)}});
    j["traffic"] = t;
  }
  if (s.has_waypoints) {
    j["waypoints_revision"] = s.waypoints.revision;
    if (with_waypoints) {
      nlohmann::json w = nlohmann::json::array();
      for (std::uint32_t i = 0; i < s.waypoints.count && i < msg::WaypointList::kCapacity; ++i)
        if (!s.waypoints.items[i].lla) w.push_back(ned(s.waypoints.items[i].w));
      j["waypoints"] = {{"loop", s.waypoints.loop}, {"items", w}};
    }
  }
  return j;
}

}  // namespace tern::core
