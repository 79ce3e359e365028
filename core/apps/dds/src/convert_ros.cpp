// core/apps/dds/src/convert_ros.cpp: tern's sensor, status and actuator messages as rosflight_io and
// ROSplane's controller put them on the wire (rosflight_msgs, sensor_msgs), for ROSplane's
// estimator and controller and any ROS 2 node. Frames and units as rosflight_io publishes them
// (rosflight_io/src/rosflight_io.cpp, which passes the firmware's values through):
//   imu/data      body FRD (the firmware's frame, not REP-103 FLU), rad/s and specific force m/s^2
//                 (level at rest: z = -g): tern's Imu is already FRD and SI, copied as is.
//   magnetometer  body FRD, tesla (sensor_msgs/MagneticField's unit).
//   baro          altitude = ISA pressure altitude of the pressure, as the firmware's
//                 turbomath::alt (lib/turbomath/turbomath.cpp), m; pressure Pa; temperature K.
//   airspeed      velocity = sign(dp) sqrt(|dp| / (0.5 * 1.225)), as the firmware's
//                 Sensors::correct_diff_pressure (src/sensors.cpp), m/s; dp Pa; temperature K.
//   gnss          lat/lon deg, alt m above MSL, vel NED m/s, header.stamp = time of validity.
//   command       ROSplane's ControllerROS::actuator_controls_publish with its default
//                 pwm_rad_{a,e,r} = 1: mode pass-through, u[0] = delta_t, u[3] = delta_a,
//                 u[4] = delta_e, u[5] = delta_r (rad).
#include <bit>
#include <cmath>

#include "convert_util.hpp"
#include "rosflight_msgs/msg/AirspeedPubSubTypes.h"
#include "rosflight_msgs/msg/BarometerPubSubTypes.h"
#include "rosflight_msgs/msg/CommandPubSubTypes.h"
#include "rosflight_msgs/msg/GNSSPubSubTypes.h"
#include "rosflight_msgs/msg/StatusPubSubTypes.h"
#include "sensor_msgs/msg/ImuPubSubTypes.h"
#include "sensor_msgs/msg/MagneticFieldPubSubTypes.h"
#include "tern/msg/all.hpp"
#include "tern/atmosphere.hpp"

namespace tern::core::ddsi {

namespace {

/// rosflight_io's header.frame_id for imu/data and magnetometer: its `frame_id` parameter's
/// default (ROSflightIO constructor: get_parameter_or("frame_id", "world")).
constexpr const char* kRosflightFrame = "world";

template <class V3, class E>
void vector3(V3& out, const E& in) {
  out.x(in.x());
  out.y(in.y());
  out.z(in.z());
}

std::string render_vector(const char* name, const geometry_msgs::msg::Vector3& v) {
  return fmt::format("{}: [{}, {}, {}]\n", name, v.x(), v.y(), v.z());
}

void add_sensor_types(std::vector<TypeEntry>& v) {
  namespace rf = rosflight_msgs::msg;
  namespace sm = sensor_msgs::msg;
  v.push_back(entry<msg::Imu, sm::ImuPubSubType>(
      [](const msg::Imu& m, sm::Imu& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.header().frame_id(kRosflightFrame);
        // tern's IMU carries no attitude: "no estimate" per sensor_msgs/Imu (covariance[0] = -1)
        s.orientation().w(1.0);
        s.orientation_covariance()[0] = -1.0;
        vector3(s.angular_velocity(), m.gyro);
        vector3(s.linear_acceleration(), m.accel);
      },
      [](const sm::Imu& s) {
        return Text().header(s.header()).str() + render_vector("angular_velocity", s.angular_velocity()) +
               render_vector("linear_acceleration", s.linear_acceleration());
      }));
  v.push_back(entry<msg::Mag, sm::MagneticFieldPubSubType>(
      [](const msg::Mag& m, sm::MagneticField& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.header().frame_id(kRosflightFrame);
        vector3(s.magnetic_field(), m.field);
      },
      [](const sm::MagneticField& s) { return Text().header(s.header()).str() + render_vector("magnetic_field", s.magnetic_field()); }));
  v.push_back(entry<msg::Baro, rf::BarometerPubSubType>(
      [](const msg::Baro& m, rf::Barometer& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.altitude(static_cast<float>(tern::rosflight::pressure_altitude(m.pressure)));
        s.pressure(static_cast<float>(m.pressure));
        s.temperature(static_cast<float>(m.temperature));
      },
      [](const rf::Barometer& s) {
        return Text().header(s.header())("altitude", s.altitude())("pressure", s.pressure())("temperature", s.temperature()).str();
      }));
  v.push_back(entry<msg::DiffPressure, rf::AirspeedPubSubType>(
      [](const msg::DiffPressure& m, rf::Airspeed& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.velocity(static_cast<float>(tern::rosflight::indicated_airspeed(m.pressure)));
        s.differential_pressure(static_cast<float>(m.pressure));
        s.temperature(static_cast<float>(m.temperature));
      },
      [](const rf::Airspeed& s) {
        return Text()
            .header(s.header())("velocity", s.velocity())("differential_pressure", s.differential_pressure())("temperature",
                                                                                                              s.temperature())
            .str();
      }));
  v.push_back(entry<msg::Gnss, rf::GNSSPubSubType>(
      [](const msg::Gnss& m, rf::GNSS& s, Nanos epoch) {
        // rosflight_io: stamp = the fix's time (fcu_time_to_ros_time of rosflight_timestamp), frame "NED"
        const Nanos valid = m.time_of_validity + epoch;
        stamp(s.header(), valid);
        s.header().frame_id("NED");
        s.fix_type(static_cast<std::uint8_t>(m.fix_type));
        s.num_sat(m.num_sats);
        s.lat(m.lat);
        s.lon(m.lon);
        s.alt(static_cast<float>(m.alt));
        s.horizontal_accuracy(static_cast<float>(m.h_acc));
        s.vertical_accuracy(static_cast<float>(m.v_acc));
        s.vel_n(static_cast<float>(m.vel.x()));
        s.vel_e(static_cast<float>(m.vel.y()));
        s.vel_d(static_cast<float>(m.vel.z()));
        s.speed_accuracy(static_cast<float>(m.s_acc));
        // the receiver's time in the same time base as the stamp (ROS time: sim time in simulation)
        const Nanos sec = valid >= 0 ? valid / 1000000000 : (valid - 999999999) / 1000000000;
        s.gnss_unix_seconds(sec);
        s.gnss_unix_nanos(static_cast<std::int32_t>(valid - sec * 1000000000));
      },
      [](const rf::GNSS& s) {
        return Text()
            .header(s.header())("fix_type", s.fix_type())("num_sat", s.num_sat())("lat", s.lat())("lon", s.lon())("alt", s.alt())(
                "horizontal_accuracy", s.horizontal_accuracy())("vertical_accuracy", s.vertical_accuracy())("vel_n", s.vel_n())(
                "vel_e", s.vel_e())("vel_d", s.vel_d())("speed_accuracy", s.speed_accuracy())("gnss_unix_seconds", s.gnss_unix_seconds())(
                "gnss_unix_nanos", s.gnss_unix_nanos())
            .str();
      }));
}

void add_status_and_command(std::vector<TypeEntry>& v) {
  namespace rf = rosflight_msgs::msg;
  v.push_back(entry<msg::FcuStatus, rf::StatusPubSubType>(
      [](const msg::FcuStatus& m, rf::Status& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.armed(m.armed);
        s.failsafe(m.failsafe);
        // tern knows only "the pilot overrides": as the firmware's attitude and throttle switch bits
        s.rc_override(m.rc_override ? 0x03 : 0x00);
        s.offboard(m.offboard);
        s.control_mode(0);  // tern flies the FCU in pass-through only (MODE_PASS_THROUGH)
        s.error_code(static_cast<std::uint8_t>(m.error_code));
        s.num_errors(static_cast<std::int16_t>(std::popcount(m.error_code)));
        s.loop_time_us(0);  // not reported by tern's FcuStatus
      },
      [](const rf::Status& s) {
        return Text()
            .header(s.header())("armed", s.armed())("failsafe", s.failsafe())("rc_override", s.rc_override())("offboard", s.offboard())(
                "control_mode", s.control_mode())("error_code", s.error_code())("num_errors", s.num_errors())("loop_time_us",
                                                                                                              s.loop_time_us())
            .str();
      }));
  v.push_back(entry<msg::Actuators, rf::CommandPubSubType>(
      [](const msg::Actuators& m, rf::Command& s, Nanos epoch) {
        stamp(s.header(), m.stamp + epoch);
        s.mode(0);    // MODE_PASS_THROUGH
        s.ignore(0);  // IGNORE_NONE
        s.u().fill(0.0f);
        auto finite = [](double x) { return std::isfinite(x) ? static_cast<float>(x) : 0.0f; };
        s.u()[0] = finite(m.delta_t);
        s.u()[3] = finite(m.delta_a);
        s.u()[4] = finite(m.delta_e);
        s.u()[5] = finite(m.delta_r);
      },
      [](const rf::Command& s) { return Text().header(s.header())("mode", s.mode())("ignore", s.ignore())("u", s.u()).str(); }));
}

}  // namespace

void add_ros_types(std::vector<TypeEntry>& v) {
  add_sensor_types(v);
  add_status_and_command(v);
}

}  // namespace tern::core::ddsi
