// core/host/flight/flight_topics.cpp: the watched topics copied (flight_topics.hpp).
#include "flight/flight_topics.hpp"

#include "flight/host.hpp"

namespace tern::core {
namespace {

/// The latest message on `topic` into `out` when what feeds it (Host::topic_source) writes type T;
/// false when nothing feeds it, nothing was written yet, or it carries another type.
template <class T>
bool latest_message(const Host& host, const std::string& topic, T& out) {
  const OutputBase* o = host.topic_source(topic);
  if (o == nullptr || o->sequence() == 0 || o->type().name != T::type_name) return false;
  out = *static_cast<const T*>(o->data());
  return true;
}

}  // namespace

bool TopicTap::take(const Host& host, Nanos now) {
  if (now == 0) next_ = 0;  // a new flight
  if (now < next_) return false;
  next_ = now + period_;
  FlightTopics& s = topics_;
  s.t = now;
  s.has_state = latest_message(host, "state", s.state);
  s.has_command = latest_message(host, "controller_command", s.command);
  s.has_internals = latest_message(host, "controller_internals", s.internals);
  s.has_actuators = latest_message(host, "actuators", s.actuators);
  s.has_phase = latest_message(host, "flight_phase", s.phase);
  s.has_path = latest_message(host, "current_path", s.path);
  s.has_rc = latest_message(host, "rc", s.rc);
  s.has_gnss = latest_message(host, "gnss", s.gnss);
  s.has_waypoints = latest_message(host, "waypoints", s.waypoints);
  const OutputBase* lists = host.topic_source("waypoints");
  s.waypoints_seq = lists != nullptr ? lists->sequence() : 0;
  return true;
}

}  // namespace tern::core
