#include "safety/failsafe_station.hpp"

#include <cmath>

#include <spdlog/spdlog.h>

#include "safety/phase_machine.hpp"

namespace tern::core {

namespace {
bool valid_fix(const msg::Gnss& g) { return g.fix_type >= msg::FixType::fix_3d && std::isfinite(g.lat) && std::isfinite(g.lon); }
}  // namespace

FailsafeStation::FailsafeStation(std::shared_ptr<spdlog::logger> log) : log_(std::move(log)) {
  terminate_out_.set_identity("actuators", "the failsafe's flight termination command");
}

void FailsafeStation::configure(const FailsafeConfig& config) {
  std::lock_guard lk(mu_);
  base_ = config;
}

void FailsafeStation::set_zones(std::vector<FenceZone> zones) {
  std::lock_guard lk(mu_);
  zones_ = std::move(zones);
  changed_ = true;
}

void FailsafeStation::set_rally(std::vector<Eigen::Vector3d> rally) {
  std::lock_guard lk(mu_);
  rally_ = std::move(rally);
  changed_ = true;
}

FailsafeConfig FailsafeStation::effective() const {
  FailsafeConfig c = base_;
  if (zones_) {
    c.geofence.zones = *zones_;
    c.geofence.enabled = c.geofence.enabled || !zones_->empty();
  }
  if (rally_) c.rally = *rally_;
  return c;
}

FailsafeStation::Geometry FailsafeStation::geometry() const {
  std::lock_guard lk(mu_);
  const FailsafeConfig c = effective();
  return {c.geofence.zones, c.rally};
}

FailsafeStation::FenceStatus FailsafeStation::fence_status() const {
  return {fence_enabled_.load(std::memory_order_relaxed), fence_breached_.load(std::memory_order_relaxed)};
}

void FailsafeStation::start_flight(const FailsafeConfig& config, const PortGraph& graph) {
  configure(config);
  {
    std::lock_guard lk(mu_);
    monitor_.set_config(effective());
    changed_ = false;
  }
  fence_enabled_ = monitor_.config().geofence.enabled && monitor_.config().geofence.limits();
  fence_breached_ = false;
  monitor_.restart();
  state_ = graph.writer_of<msg::State>("state");
  gnss_ = graph.writer_of<msg::Gnss>("gnss");
  gnss_seen_ = gnss_ ? gnss_->sequence() : 0;
  last_fix_.reset();
  link_heard_.reset();
  heard_seen_ = heard_.load(std::memory_order_relaxed);  // heard between flights does not count
  events_.clear();
  terminated_ = false;
}

void FailsafeStation::tick(Nanos now, const PhaseMachine* phase_machine, RemoteQueue& remote, PortGraph& graph) {
  const msg::Phase phase = phase_machine ? phase_machine->phase() : msg::Phase::preflight;
  const bool airborne = msg::airborne(phase);
  const double max_deflection = phase_machine ? phase_machine->max_deflection() : 0.0;
  if (gnss_ && gnss_->sequence() != gnss_seen_) {
    gnss_seen_ = gnss_->sequence();
    if (valid_fix(*static_cast<const msg::Gnss*>(gnss_->data()))) last_fix_ = now;
  }
  if (const std::uint64_t h = heard_.load(std::memory_order_relaxed); h != heard_seen_) {
    heard_seen_ = h;
    link_heard_ = now;
  }
  {
    std::lock_guard lk(mu_);
    if (changed_) {
      monitor_.set_config(effective());
      changed_ = false;
      fence_enabled_ = monitor_.config().geofence.enabled && monitor_.config().geofence.limits();
    }
  }
  FailsafeInputs in;
  in.now = now;
  in.airborne = airborne;
  in.state = state_ && state_->sequence() > 0 ? static_cast<const msg::State*>(state_->data()) : nullptr;
  in.last_fix = last_fix_;
  in.link_heard = link_heard_;
  in.landing = msg::on_final(phase);
  for (const FailsafeEvent& e : monitor_.check(in)) act(e, max_deflection, remote);
  fence_breached_.store(monitor_.fence_breached(), std::memory_order_relaxed);
  if (terminated_) {
    msg::Actuators a = terminate_out_.last();
    a.stamp = now;
    terminate_out_.publish(a);
    graph.route_topic("actuators", &terminate_out_);
  }
}

void FailsafeStation::act(const FailsafeEvent& e, double max_deflection, RemoteQueue& remote) {
  events_.push_back(e);
  log_->log(e.action == "none" ? spdlog::level::info : spdlog::level::warn, "t={:.3f} s: failsafe {}: {}", to_seconds(e.t), e.cause,
            e.detail);
  if (e.action == "terminate") {
    terminated_ = true;
    terminate_out_.publish(termination_command(e.terminate, max_deflection));
    return;
  }
  if (e.action != "loiter" && e.action != "return_home") return;
  if (!remote.takes_mission_edits()) {
    log_->error("t={:.3f} s: failsafe {}: no plugin instance reads 'mission_edit' (add a path_planner): the {} is not flown",
                to_seconds(e.t), e.cause, e.action);
    return;
  }
  msg::MissionEdit edit;
  edit.id = static_cast<std::uint32_t>(events_.size());
  edit.op = msg::MissionEdit::add;
  edit.set_current_wp = true;
  edit.publish_now = true;
  // a return to a rally point (centre away from home) is a loiter there
  const bool home = e.centre.x() == 0.0 && e.centre.y() == 0.0;
  edit.waypoint.type = e.action == "loiter" || !home ? msg::Waypoint::loiter : msg::Waypoint::return_home;
  edit.waypoint.w = e.centre;
  edit.waypoint.loiter_radius = e.radius;
  remote.edit_mission(edit, /*own=*/true);  // never refused, however many requests wait
}

}  // namespace tern::core
