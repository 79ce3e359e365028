// core/apps/dds/src/convert.cpp: tern messages -> DDS samples (ROSplane's types where ROSplane has
// one, tern_msgs otherwise) and DDS samples -> text (for `tern echo`).
#include <array>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "convert_util.hpp"
#include "rosplane_msgs/msg/ControllerCommandsPubSubTypes.h"
#include "rosplane_msgs/msg/ControllerInternalsPubSubTypes.h"
#include "rosplane_msgs/msg/CurrentPathPubSubTypes.h"
#include "rosplane_msgs/msg/StatePubSubTypes.h"
#include "rosplane_msgs/msg/WaypointPubSubTypes.h"
#include "tern/msg/all.hpp"
#include "tern/reflect.hpp"
#include "tern_msgs/msg/SensorsPubSubTypes.h"
#include "tern_msgs/msg/VehiclePubSubTypes.h"

namespace tern::core::ddsi {

namespace {

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

std::vector<TypeEntry> build() {
  std::vector<TypeEntry> v;
  using namespace rosplane_msgs::msg;
  namespace tm = tern_msgs::msg;
  v.push_back(entry<msg::State, StatePubSubType>(
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
      }));
  v.push_back(entry<msg::ControllerCommand, ControllerCommandsPubSubType>(
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
      }));
  v.push_back(entry<msg::ControllerInternals, ControllerInternalsPubSubType>(
      [](const msg::ControllerInternals& m, ControllerInternals& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.theta_c(static_cast<float>(m.theta_c));
        s.phi_c(static_cast<float>(m.phi_c));
        s.alt_zone(rosplane_zone(m.alt_zone));
      },
      [](const ControllerInternals& s) {
        return Text().header(s.header())("theta_c", s.theta_c())("phi_c", s.phi_c())("alt_zone", s.alt_zone()).str();
      }));
  v.push_back(entry<msg::CurrentPath, CurrentPathPubSubType>(
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
      }));
  v.push_back(
      entry<msg::Waypoint, WaypointPubSubType>([](const msg::Waypoint& m, Waypoint& s, Nanos) { to_waypoint(m, s); }, render_waypoint));
  v.push_back(entry<msg::WaypointList, tm::WaypointListPubSubType>(
      [](const msg::WaypointList& m, tm::WaypointList& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.revision(m.revision);
        s.loop(m.loop);
        s.loops(m.loops);
        s.waypoints().resize(std::min<std::size_t>(m.count, msg::WaypointList::kCapacity));
        for (std::size_t i = 0; i < s.waypoints().size(); ++i) {
          to_waypoint(m.items[i], s.waypoints()[i]);
          s.waypoints()[i].header(s.header());
        }
      },
      [](const tm::WaypointList& s) {
        std::string out =
            Text().header(s.header())("revision", s.revision())("loop", s.loop())("loops", s.loops())("count", s.waypoints().size()).str();
        for (std::size_t i = 0; i < s.waypoints().size(); ++i) {
          const auto& w = s.waypoints()[i];
          out += fmt::format("waypoint[{}]: w [{}, {}, {}] lla {} chi_d {} use_chi {} va_d {}\n", i, w.w()[0], w.w()[1], w.w()[2], w.lla(),
                             w.chi_d(), w.use_chi(), w.va_d());
        }
        return out;
      }));
  v.push_back(waypoint_path_entry());
  v.push_back(entry<msg::Actuators, tm::ActuatorsPubSubType>(
      [](const msg::Actuators& m, tm::Actuators& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.delta_a(m.delta_a);
        s.delta_e(m.delta_e);
        s.delta_r(m.delta_r);
        s.delta_t(m.delta_t);
        s.brake(m.brake);
      },
      [](const tm::Actuators& s) {
        return Text()
            .header(s.header())("delta_a", s.delta_a())("delta_e", s.delta_e())("delta_r", s.delta_r())("delta_t", s.delta_t())("brake",
                                                                                                                                s.brake())
            .str();
      }));
  v.push_back(entry<msg::FlightPhase, tm::FlightPhasePubSubType>(
      [](const msg::FlightPhase& m, tm::FlightPhase& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.phase(static_cast<std::uint8_t>(m.phase));
        s.previous(static_cast<std::uint8_t>(m.previous));
        std_msgs::msg::Header h;
        stamp(h, m.since + epoch);
        s.since(h.stamp());
        s.phase_name(std::string(msg::phase_name(m.phase)));
      },
      [](const tm::FlightPhase& s) {
        return Text()
            .header(s.header())("phase", s.phase())("previous", s.previous())(
                "since", fmt::format("{}.{:09d}", s.since().sec(), s.since().nanosec()))("phase_name", s.phase_name())
            .str();
      }));
  v.push_back(entry<msg::Imu, tm::ImuPubSubType>(
      [](const msg::Imu& m, tm::Imu& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        vec<3>(s.accel(), m.accel);
        vec<3>(s.gyro(), m.gyro);
        s.temperature(m.temperature);
      },
      [](const tm::Imu& s) {
        return Text().header(s.header())("accel", s.accel())("gyro", s.gyro())("temperature", s.temperature()).str();
      }));
  v.push_back(entry<msg::Gnss, tm::GnssPubSubType>(
      [](const msg::Gnss& m, tm::Gnss& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.fix_type(static_cast<std::uint8_t>(m.fix_type));
        s.num_sats(m.num_sats);
        s.lat(m.lat);
        s.lon(m.lon);
        s.alt(m.alt);
        vec<3>(s.vel(), m.vel);
        s.h_acc(m.h_acc);
        s.v_acc(m.v_acc);
        s.s_acc(m.s_acc);
        to_time(s.time_of_validity(), m.time_of_validity + epoch);
      },
      [](const tm::Gnss& s) {
        return Text()
            .header(s.header())("fix_type", s.fix_type())("num_sats", s.num_sats())("lat", s.lat())("lon", s.lon())("alt", s.alt())(
                "vel", s.vel())("h_acc", s.h_acc())("v_acc", s.v_acc())("s_acc", s.s_acc())(
                "time_of_validity", fmt::format("{}.{:09d}", s.time_of_validity().sec(), s.time_of_validity().nanosec()))
            .str();
      }));
  v.push_back(entry<msg::Baro, tm::BaroPubSubType>(
      [](const msg::Baro& m, tm::Baro& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.pressure(m.pressure);
        s.temperature(m.temperature);
      },
      [](const tm::Baro& s) { return Text().header(s.header())("pressure", s.pressure())("temperature", s.temperature()).str(); }));
  v.push_back(entry<msg::DiffPressure, tm::DiffPressurePubSubType>(
      [](const msg::DiffPressure& m, tm::DiffPressure& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.pressure(m.pressure);
        s.temperature(m.temperature);
      },
      [](const tm::DiffPressure& s) { return Text().header(s.header())("pressure", s.pressure())("temperature", s.temperature()).str(); }));
  v.push_back(entry<msg::Mag, tm::MagPubSubType>(
      [](const msg::Mag& m, tm::Mag& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        vec<3>(s.field(), m.field);
      },
      [](const tm::Mag& s) { return Text().header(s.header())("field", s.field()).str(); }));
  v.push_back(entry<msg::Rc, tm::RcPubSubType>(
      [](const msg::Rc& m, tm::Rc& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.roll(m.roll);
        s.pitch(m.pitch);
        s.yaw(m.yaw);
        s.throttle(m.throttle);
        vec<4>(s.aux(), m.aux);
        s.rc_override(m.rc_override);
        s.failsafe(m.failsafe);
      },
      [](const tm::Rc& s) {
        return Text()
            .header(s.header())("roll", s.roll())("pitch", s.pitch())("yaw", s.yaw())("throttle", s.throttle())("aux", s.aux())(
                "rc_override", s.rc_override())("failsafe", s.failsafe())
            .str();
      }));
  v.push_back(entry<msg::FcuStatus, tm::FcuStatusPubSubType>(
      [](const msg::FcuStatus& m, tm::FcuStatus& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.armed(m.armed);
        s.failsafe(m.failsafe);
        s.rc_override(m.rc_override);
        s.offboard(m.offboard);
        s.error_code(m.error_code);
        s.battery_voltage(m.battery_voltage);
        s.battery_current(m.battery_current);
      },
      [](const tm::FcuStatus& s) {
        return Text()
            .header(s.header())("armed", s.armed())("failsafe", s.failsafe())("rc_override", s.rc_override())("offboard", s.offboard())(
                "error_code", s.error_code())("battery_voltage", s.battery_voltage())("battery_current", s.battery_current())
            .str();
      }));
  add_ros_types(v);
  return v;
}

}  // namespace

std::string ros_type_name(const std::string& dds_type) {
  std::string out;
  for (std::size_t i = 0; i < dds_type.size();) {
    if (dds_type.compare(i, 8, "::dds_::") == 0) {
      out += '/';
      i += 8;
    } else if (dds_type.compare(i, 2, "::") == 0) {
      out += '/';
      i += 2;
    } else {
      out += dds_type[i++];
    }
  }
  if (!out.empty() && out.back() == '_') out.pop_back();
  return out;
}

const std::vector<TypeEntry>& all_types() {
  static const std::vector<TypeEntry> types = build();
  return types;
}

const TypeEntry* find_type(std::string_view tern_type, std::string_view ros_type) {
  for (const auto& e : all_types())
    if (e.tern_type == tern_type && (ros_type.empty() || e.ros_type == ros_type)) return &e;
  return nullptr;
}

const TypeEntry* find_dds_type(std::string_view dds_type) {
  for (const auto& e : all_types())
    if (e.dds_type == dds_type) return &e;
  return nullptr;
}

}  // namespace tern::core::ddsi
