// core/apps/mavlink/flight_view.cpp: the flight as the ground station's handlers see it (flight_view.hpp).
#include "mavlink/flight_view.hpp"

#include "flight/host.hpp"
#include "tern/msg/all.hpp"

namespace tern::core::mavlink {
namespace {
constexpr Nanos kViewPeriod = 20'000'000;  // flight time between copies, ns (50 Hz)
}

FlightWatch::FlightWatch(Host& host) : host_(host) {
  id_ = host.add_tick_observer([this](Nanos now) { observe(now); });
}

FlightWatch::~FlightWatch() { host_.remove_tick_observer(id_); }

FlightView FlightWatch::view() const {
  std::lock_guard lk(mu_);
  FlightView v = view_;
  v.flying = host_.flying();
  return v;
}

void FlightWatch::observe(Nanos now) {
  if (now == 0) {  // a new flight: its planner publishes its lists from 1 again
    next_ = 0;
    seen_seq_ = 0;
  }
  if (now < next_) return;
  next_ = now + kViewPeriod;
  msg::State s;
  msg::FlightPhase phase;
  msg::CurrentPath path;
  const bool has_state = latest_message(host_, "state", s) && s.origin_valid;
  const bool has_phase = latest_message(host_, "flight_phase", phase);
  const bool has_path = latest_message(host_, "current_path", path);
  std::shared_ptr<msg::WaypointList> list;
  const OutputBase* wps = host_.topic_source("waypoints");
  const std::uint64_t seq = wps != nullptr ? wps->sequence() : 0;
  if (seq != seen_seq_ && seq > 0) {
    list = std::make_shared<msg::WaypointList>();
    latest_message(host_, "waypoints", *list);
  }
  seen_seq_ = seq;
  std::lock_guard lk(mu_);
  if (has_state) {
    view_.has_state = true;
    view_.origin = {s.origin_lat, s.origin_lon, s.origin_alt};
    view_.p_ned = {s.p_n, s.p_e, s.p_d};
  }
  view_.has_phase = has_phase;
  if (has_phase) view_.phase = phase.phase;
  view_.waypoint_index = has_path ? path.waypoint_index : -1;
  view_.list_seq = seq;
  if (list) view_.list = std::move(list);
}

}  // namespace tern::core::mavlink
