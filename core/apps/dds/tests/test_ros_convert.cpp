// core/apps/dds/tests/test_ros_convert.cpp: tern messages as rosflight_io and ROSplane put them on the
// wire (src/convert_ros.cpp, the waypoint_path stream in src/convert.cpp), without DDS.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "dds_internal.hpp"
#include "rosflight_msgs/msg/AirspeedPubSubTypes.h"
#include "rosflight_msgs/msg/BarometerPubSubTypes.h"
#include "rosflight_msgs/msg/CommandPubSubTypes.h"
#include "rosflight_msgs/msg/GNSSPubSubTypes.h"
#include "rosflight_msgs/msg/StatusPubSubTypes.h"
#include "rosplane_msgs/msg/WaypointPubSubTypes.h"
#include "sensor_msgs/msg/ImuPubSubTypes.h"
#include "tern/msg/all.hpp"

using namespace tern;
using namespace tern::core;

namespace {

/// Converts `m` with the entry for (tern type of M, ros_type) and returns every sample written.
template <class Sample, class M>
std::vector<Sample> convert(const M& m, const char* ros_type, Nanos epoch = 0) {
  const ddsi::TypeEntry* e = ddsi::find_type(M::type_name, ros_type);
  REQUIRE_MESSAGE(e != nullptr, ros_type);
  CHECK(e->ros_type == ros_type);
  auto sample = e->make_sample();
  std::vector<Sample> out;
  e->convert(&m, sample.get(), epoch, [&] { out.push_back(*static_cast<Sample*>(sample.get())); });
  return out;
}

double stamp_s(const builtin_interfaces::msg::Time& t) { return t.sec() + t.nanosec() * 1e-9; }

}  // namespace

TEST_CASE("ros convert: without a ROS type a tern type keeps tern's own DDS type") {
  CHECK(ddsi::find_type("tern/Imu")->dds_type == "tern_msgs::msg::dds_::Imu_");
  CHECK(ddsi::find_type("tern/Imu", "sensor_msgs/msg/Imu")->dds_type == "sensor_msgs::msg::dds_::Imu_");
  CHECK(ddsi::find_type("tern/Imu", "sensor_msgs/msg/MagneticField") == nullptr);
  CHECK(ddsi::find_type("tern/WaypointList")->dds_type == "tern_msgs::msg::dds_::WaypointList_");
}

TEST_CASE("ros convert: imu/data is FRD and SI as rosflight_io's, stamped in ROS time") {
  msg::Imu m;
  m.stamp = 2'500'000'000;
  m.accel = Eigen::Vector3d(0.1, -0.2, -9.81);
  m.gyro = Eigen::Vector3d(0.01, 0.02, -0.03);
  const auto s = convert<sensor_msgs::msg::Imu>(m, "sensor_msgs/msg/Imu", 1'700'000'000'000'000'000);
  REQUIRE(s.size() == 1);
  CHECK(s[0].header().stamp().sec() == 1'700'000'002);
  CHECK(s[0].header().stamp().nanosec() == 500'000'000u);
  CHECK(s[0].header().frame_id() == "world");
  CHECK(s[0].linear_acceleration().z() == -9.81);  // specific force, FRD: level at rest z = -g
  CHECK(s[0].angular_velocity().z() == -0.03);
  CHECK(s[0].orientation_covariance()[0] == -1.0);  // no orientation estimate
}

TEST_CASE("ros convert: baro altitude and airspeed as the ROSflight firmware computes them") {
  msg::Baro b;
  b.pressure = 89874.6;  // ISA at 1000 m
  const auto bs = convert<rosflight_msgs::msg::Barometer>(b, "rosflight_msgs/msg/Barometer");
  REQUIRE(bs.size() == 1);
  CHECK(bs[0].altitude() == doctest::Approx(1000.0).epsilon(1e-3));
  CHECK(bs[0].pressure() == doctest::Approx(89874.6));
  msg::DiffPressure d;
  d.pressure = 0.5 * 1.225 * 15.0 * 15.0;
  const auto ds = convert<rosflight_msgs::msg::Airspeed>(d, "rosflight_msgs/msg/Airspeed");
  CHECK(ds[0].velocity() == doctest::Approx(15.0));
  d.pressure = -0.5 * 1.225 * 4.0;
  CHECK(convert<rosflight_msgs::msg::Airspeed>(d, "rosflight_msgs/msg/Airspeed")[0].velocity() == doctest::Approx(-2.0));
}

TEST_CASE("ros convert: gnss is stamped at its time of validity; status and command as ROSplane reads and writes them") {
  msg::Gnss g;
  g.stamp = 1'200'000'000;
  g.time_of_validity = 1'100'000'000;
  g.fix_type = msg::FixType::fix_3d;
  g.lat = 40.25;
  g.vel = Eigen::Vector3d(15.0, -1.0, 0.5);
  const auto gs = convert<rosflight_msgs::msg::GNSS>(g, "rosflight_msgs/msg/GNSS");
  CHECK(stamp_s(gs[0].header().stamp()) == doctest::Approx(1.1));
  CHECK(gs[0].fix_type() == 3);
  CHECK(gs[0].lat() == 40.25);
  CHECK(gs[0].vel_e() == -1.0f);
  CHECK(gs[0].gnss_unix_seconds() == 1);
  CHECK(gs[0].gnss_unix_nanos() == 100'000'000);
  msg::FcuStatus f;
  f.armed = true;
  f.rc_override = true;
  f.error_code = 0x05;
  const auto fs = convert<rosflight_msgs::msg::Status>(f, "rosflight_msgs/msg/Status");
  CHECK(fs[0].armed());
  CHECK(fs[0].rc_override() == 0x03);
  CHECK(fs[0].num_errors() == 2);
  msg::Actuators a;
  a.delta_a = 0.1;
  a.delta_e = -0.2;
  a.delta_r = std::nan("");
  a.delta_t = 0.6;
  const auto cs = convert<rosflight_msgs::msg::Command>(a, "rosflight_msgs/msg/Command");
  CHECK(cs[0].mode() == 0);
  CHECK(cs[0].ignore() == 0);
  CHECK(cs[0].u()[0] == 0.6f);
  CHECK(cs[0].u()[3] == 0.1f);
  CHECK(cs[0].u()[4] == -0.2f);
  CHECK(cs[0].u()[5] == 0.0f);  // not finite: 0, as ROSplane's controller does
}

TEST_CASE("ros convert: a waypoint list is a clear, then one Waypoint per item (waypoint_path)") {
  msg::WaypointList l;
  l.stamp = 3'000'000'000;
  l.count = 2;
  l.items[0].w = Eigen::Vector3d(100.0, 0.0, -50.0);
  l.items[0].Va_d = 15.0;
  l.items[1].w = Eigen::Vector3d(100.0, 200.0, -60.0);
  l.items[1].Va_d = 16.0;
  l.items[1].use_chi = true;
  const auto s = convert<rosplane_msgs::msg::Waypoint>(l, "rosplane_msgs/msg/Waypoint");
  REQUIRE(s.size() == 3);
  CHECK(s[0].clear_wp_list());
  CHECK_FALSE(s[1].clear_wp_list());
  CHECK(s[1].w()[2] == -50.0f);
  CHECK(s[2].w()[1] == 200.0f);
  CHECK(s[2].use_chi());
  CHECK(s[2].va_d() == 16.0f);
  for (const auto& w : s) CHECK(w.header().stamp().sec() == 3);
}
