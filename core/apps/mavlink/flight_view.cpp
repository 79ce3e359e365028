// core/apps/mavlink/flight_view.cpp: the flight as the ground station's handlers see it (flight_view.hpp).
#include "mavlink/flight_view.hpp"

#include "flight/host.hpp"

namespace tern::core::mavlink {
namespace {
constexpr Nanos kViewPeriod = 20'000'000;  // flight time between copies, ns (50 Hz)
}

FlightWatch::FlightWatch(Host& host) : host_(host), topics_(kViewPeriod) {
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
  if (now == 0) seen_seq_ = 0;  // a new flight: its planner publishes its lists from 1 again
  if (!topics_.take(host_, now)) return;
  const FlightTopics& t = topics_.topics();
  const msg::State& s = t.state;
  const bool has_state = t.has_state && s.origin_valid;
  const bool has_phase = t.has_phase;
  const std::uint64_t seq = t.waypoints_seq;
  std::shared_ptr<msg::WaypointList> list;
  if (seq != seen_seq_ && seq > 0) list = std::make_shared<msg::WaypointList>(t.waypoints);
  seen_seq_ = seq;
  std::lock_guard lk(mu_);
  if (has_state) {
    view_.has_state = true;
    view_.origin = {s.origin_lat, s.origin_lon, s.origin_alt};
    view_.p_ned = {s.p_n, s.p_e, s.p_d};
  }
  view_.has_phase = has_phase;
  if (has_phase) view_.phase = t.phase.phase;
  view_.waypoint_index = t.has_path ? t.path.waypoint_index : -1;
  view_.list_seq = seq;
  if (list) view_.list = std::move(list);
}

}  // namespace tern::core::mavlink
