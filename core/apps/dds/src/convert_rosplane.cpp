// core/apps/dds/src/convert_rosplane.cpp: tern's estimate, commands, path and waypoints as ROSplane
// 2.0 puts them on the wire (rosplane_msgs, checked against ROSplane's .msg files by ctest dds),
// for ROSplane's nodes and any ROS 2 node. See convert_rosplane.hpp.
#include "convert_rosplane.hpp"

#include <fmt/format.h>

#include "convert_util.hpp"
#include "rosplane_msgs/msg/ControllerCommandsPubSubTypes.h"
#include "rosplane_msgs/msg/ControllerInternalsPubSubTypes.h"
#include "rosplane_msgs/msg/CurrentPathPubSubTypes.h"
#include "rosplane_msgs/msg/StatePubSubTypes.h"
#include "rosplane_msgs/msg/WaypointPubSubTypes.h"
#include "tern/msg/all.hpp"

namespace tern::core::ddsi {

namespace {

using namespace rosplane_msgs::msg;

std::uint8_t rosplane_zone(std::uint8_t tern_phase) {
  // ROSplane: 0 take-off, 1 climb, 2 descend, 3 altitude hold
  switch (static_cast<msg::Phase>(tern_phase)) {
    case msg::Phase::preflight:  // on the ground before the takeoff: ROSplane has no such zone
    case msg::Phase::takeoff: return 0;
    case msg::Phase::climb: return 1;
    case msg::Phase::landing:
    case msg::Phase::approach:
    case msg::Phase::flare:
    case msg::Phase::rollout:
    case msg::Phase::stopped: return 2;
    case msg::Phase::cruise:
    case msg::Phase::loiter: return 3;
  }
  return 3;
}

void to_waypoint(const msg::Waypoint& w, rosplane_msgs::msg::Waypoint& o) {
  vec<3>(o.w(), w.w);
  o.lla(w.lla);
  o.chi_d(static_cast<float>(w.chi_d));
  o.use_chi(w.use_chi);
  o.va_d(static_cast<float>(w.Va_d));
  o.set_current(false);
  o.clear_wp_list(false);
}

std::string render_waypoint(const rosplane_msgs::msg::Waypoint& s) {
  return Text()
      .header(s.header())("w", s.w())("lla", s.lla())("chi_d", s.chi_d())("use_chi", s.use_chi())("va_d", s.va_d())(
          "set_current", s.set_current())("clear_wp_list", s.clear_wp_list())
      .str();
}

/// A waypoint list as ROSplane's path planner publishes it on waypoint_path
/// (path_planner_waypoints.cpp: clear_path, waypoint_publish): one Waypoint with clear_wp_list,
/// then one Waypoint per item, each stamped with the list's stamp.
TypeEntry waypoint_path_entry() {
  using rosplane_msgs::msg::Waypoint, rosplane_msgs::msg::WaypointPubSubType;
  TypeEntry e = entry<msg::WaypointList, WaypointPubSubType>([](const msg::WaypointList&, Waypoint&, Nanos) {}, render_waypoint);
  e.convert = [](const void* m, void* sample, Nanos epoch, const std::function<void()>& write) {
    const auto& list = *static_cast<const msg::WaypointList*>(m);
    auto& s = *static_cast<Waypoint*>(sample);
    s = Waypoint();
    stamp(s.header(), list.stamp + epoch);
    s.clear_wp_list(true);
    write();
    for (std::uint32_t i = 0; i < list.count && i < msg::WaypointList::kCapacity; ++i) {
      to_waypoint(list.items[i], s);
      write();
    }
  };
  return e;
}

TypeEntry state_entry() {
  return entry<msg::State, StatePubSubType>(
      [](const msg::State& m, State& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.p_n(static_cast<float>(m.p_n));
        s.p_e(static_cast<float>(m.p_e));
        s.p_d(static_cast<float>(m.p_d));
        s.v_x(static_cast<float>(m.u));
        s.v_y(static_cast<float>(m.v));
        s.v_z(static_cast<float>(m.w));
        s.p(static_cast<float>(m.p));
        s.q(static_cast<float>(m.q));
        s.r(static_cast<float>(m.r));
        s.phi(static_cast<float>(m.phi));
        s.theta(static_cast<float>(m.theta));
        s.psi(static_cast<float>(m.psi));
        s.b_x(static_cast<float>(m.b_x));
        s.b_y(static_cast<float>(m.b_y));
        s.b_z(static_cast<float>(m.b_z));
        s.quat().w(m.quat.w());
        s.quat().x(m.quat.x());
        s.quat().y(m.quat.y());
        s.quat().z(m.quat.z());
        s.initial_lat(m.origin_lat);
        s.initial_lon(m.origin_lon);
        s.initial_alt(m.origin_alt);
        s.w_n(static_cast<float>(m.w_n));
        s.w_e(static_cast<float>(m.w_e));
        s.va(static_cast<float>(m.Va));
        s.alpha(static_cast<float>(m.alpha));
        s.beta(static_cast<float>(m.beta));
        s.chi(static_cast<float>(m.chi));
      },
      [](const State& s) {
        return Text()
            .header(s.header())("p_n", s.p_n())("p_e", s.p_e())("p_d", s.p_d())("v_x", s.v_x())("v_y", s.v_y())("v_z", s.v_z())("p", s.p())(
                "q", s.q())("r", s.r())("phi", s.phi())("theta", s.theta())("psi", s.psi())("b_x", s.b_x())("b_y", s.b_y())("b_z", s.b_z())(
                "quat.x", s.quat().x())("quat.y", s.quat().y())("quat.z", s.quat().z())("quat.w", s.quat().w())(
                "initial_lat", s.initial_lat())("initial_lon", s.initial_lon())("initial_alt", s.initial_alt())("w_n", s.w_n())(
                "w_e", s.w_e())("va", s.va())("alpha", s.alpha())("beta", s.beta())("chi", s.chi())
            .str();
      });
}

TypeEntry controller_command_entry() {
  return entry<msg::ControllerCommand, ControllerCommandsPubSubType>(
      [](const msg::ControllerCommand& m, ControllerCommands& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.va_c(static_cast<float>(m.Va_c));
        s.h_c(static_cast<float>(m.h_c));
        s.chi_c(static_cast<float>(m.chi_c));
        s.phi_ff(static_cast<float>(m.phi_ff));
        vec<4>(s.aux(), m.aux);
        s.aux_valid(m.aux_valid);
        s.theta_c(static_cast<float>(m.theta_c));
        s.phi_c(static_cast<float>(m.phi_c));
      },
      [](const ControllerCommands& s) {
        return Text()
            .header(s.header())("va_c", s.va_c())("h_c", s.h_c())("chi_c", s.chi_c())("phi_ff", s.phi_ff())("aux", s.aux())(
                "aux_valid", s.aux_valid())("theta_c", s.theta_c())("phi_c", s.phi_c())
            .str();
      });
}

TypeEntry controller_internals_entry() {
  return entry<msg::ControllerInternals, ControllerInternalsPubSubType>(
      [](const msg::ControllerInternals& m, ControllerInternals& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.theta_c(static_cast<float>(m.theta_c));
        s.phi_c(static_cast<float>(m.phi_c));
        s.alt_zone(rosplane_zone(m.alt_zone));
      },
      [](const ControllerInternals& s) {
        return Text().header(s.header())("theta_c", s.theta_c())("phi_c", s.phi_c())("alt_zone", s.alt_zone()).str();
      });
}

TypeEntry current_path_entry() {
  return entry<msg::CurrentPath, CurrentPathPubSubType>(
      [](const msg::CurrentPath& m, CurrentPath& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.path_type(m.path_type);
        s.va_d(static_cast<float>(m.Va_d));
        vec<3>(s.r(), m.r);
        vec<3>(s.q(), m.q);
        vec<3>(s.c(), m.c);
        s.rho(static_cast<float>(m.rho));
        s.lamda(m.lambda);
      },
      [](const CurrentPath& s) {
        return Text()
            .header(s.header())("path_type", s.path_type())("va_d", s.va_d())("r", s.r())("q", s.q())("c", s.c())("rho", s.rho())("lamda",
                                                                                                                                  s.lamda())
            .str();
      });
}

TypeEntry waypoint_entry() {
  return entry<msg::Waypoint, WaypointPubSubType>([](const msg::Waypoint& m, Waypoint& s, Nanos) { to_waypoint(m, s); }, render_waypoint);
}

}  // namespace

void list_waypoint(const msg::Waypoint& item, const std_msgs::msg::Header& list_header, rosplane_msgs::msg::Waypoint& out) {
  to_waypoint(item, out);
  out.header(list_header);
}

std::string render_list_waypoint(std::size_t index, const rosplane_msgs::msg::Waypoint& w) {
  return fmt::format("waypoint[{}]: w [{}, {}, {}] lla {} chi_d {} use_chi {} va_d {}\n", index, w.w()[0], w.w()[1], w.w()[2], w.lla(),
                     w.chi_d(), w.use_chi(), w.va_d());
}

void add_rosplane_types(std::vector<TypeEntry>& v) {
  v.push_back(state_entry());
  v.push_back(controller_command_entry());
  v.push_back(controller_internals_entry());
  v.push_back(current_path_entry());
  v.push_back(waypoint_entry());
  v.push_back(waypoint_path_entry());
}

}  // namespace tern::core::ddsi
