// The 3-D scene's frames (scene_channels.hpp): NED -> ENU and FRD -> FLU as REP-103 defines them
// (an attitude's body axes land where the Euler angles say), the channels each tern topic feeds,
// a fleet vehicle's frames under its prefix, the model drawn once, and the CDR bytes of a
// TFMessage as ROS 2 lays them out (the node test decodes whole flights with Foxglove's readers).
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "ros/scene_channels.hpp"
#include "ros/scene_msgs.hpp"
#include "tern/math.hpp"
#include "tern/msg/state.hpp"

using namespace tern;
using namespace tern::core;

namespace {

Eigen::Quaterniond frd_to_ned(double phi, double theta, double psi) {
  return Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitX());
}

std::vector<std::string> names(const std::vector<RosChannel>& cs) {
  std::vector<std::string> out;
  for (const auto& c : cs) out.push_back(c.topic);
  return out;
}

bool contains(const std::string& bytes, const std::string& text) { return bytes.find(text) != std::string::npos; }

}  // namespace

TEST_CASE("scene: NED positions and FRD attitudes become ENU and FLU (REP-103)") {
  CHECK(enu_of_ned({1.0, 2.0, -3.0}).isApprox(Eigen::Vector3d(2.0, 1.0, 3.0)));
  // heading 30 deg east of north, climbing 10 deg, right wing 20 deg down
  const double psi = 30.0 * kRadPerDeg, theta = 10.0 * kRadPerDeg, phi = 20.0 * kRadPerDeg;
  const Eigen::Matrix3d r = flu_attitude_in_enu(frd_to_ned(phi, theta, psi)).toRotationMatrix();
  const Eigen::Vector3d forward = r.col(0), left = r.col(1), up = r.col(2);
  CHECK(forward.isApprox(Eigen::Vector3d(std::sin(psi) * std::cos(theta), std::cos(psi) * std::cos(theta), std::sin(theta)), 1e-12));
  CHECK(left.z() == doctest::Approx(std::sin(phi) * std::cos(theta)));  // the left wing up when banked right
  CHECK(up.z() == doctest::Approx(std::cos(phi) * std::cos(theta)));
  // level, nose north: FLU x is ENU y (yaw +90 deg about z)
  const Eigen::Quaterniond level = flu_attitude_in_enu(Eigen::Quaterniond::Identity());
  CHECK(level.toRotationMatrix().isApprox(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix()));
}

TEST_CASE("scene: the channels each topic feeds, a fleet vehicle's frames under its prefix") {
  SceneOptions o;
  o.frame_prefix = "uav1/";
  o.span = 2.0;
  o.chord = 0.2;
  o.nose_x = 0.4;
  o.tail_x = -0.8;
  o.tail_z = -0.1;
  Scene scene(o);
  CHECK(names(scene.channels_of("truth", "tern/State")) ==
        std::vector<std::string>{"/tf", "/tern/markers/aircraft", "/tern/markers/track", "/tern/markers/wind"});
  CHECK(names(scene.channels_of("imu", "tern/Imu")).empty());
  CHECK(names(scene.channels_of("truth", "tern/Imu")).empty());  // a topic named truth of another type
  auto truth = scene.channels_of("truth", "tern/State");
  msg::State s;
  s.stamp = 1'500'000'000;
  s.p_n = 10.0;
  s.p_e = 20.0;
  s.p_d = -30.0;
  std::vector<std::string> out;
  truth[0].encode(&s, out);
  REQUIRE(out.size() == 1);
  // CDR: header, 1 transform, stamp 1 s 500000000 ns, "map", "uav1/base_link", x y z = e n u
  const std::string& b = out[0];
  CHECK(b.substr(0, 4) == std::string("\0\1\0\0", 4));
  std::uint32_t n = 0, sec = 0, nsec = 0;
  std::memcpy(&n, b.data() + 4, 4);
  std::memcpy(&sec, b.data() + 8, 4);
  std::memcpy(&nsec, b.data() + 12, 4);
  CHECK(n == 1);
  CHECK(sec == 1);
  CHECK(nsec == 500'000'000);
  CHECK(contains(b, std::string("map\0", 4)));
  CHECK(contains(b, std::string("uav1/base_link\0", 15)));
  double xyz[3];
  std::memcpy(xyz, b.data() + b.size() - 7 * 8, sizeof xyz);
  CHECK(xyz[0] == 20.0);
  CHECK(xyz[1] == 10.0);
  CHECK(xyz[2] == 30.0);
  // the model once, in the vehicle's frame
  out.clear();
  truth[1].encode(&s, out);
  truth[1].encode(&s, out);
  REQUIRE(out.size() == 1);
  CHECK(contains(out[0], "uav1/base_link"));
  CHECK(contains(out[0], std::string("uav1/truth\0", 11)));  // its namespace too: a fleet's files opened together
}

TEST_CASE("scene: the estimate under map_estimate, placed by its origin") {
  Scene scene(SceneOptions{});
  auto truth = scene.channels_of("truth", "tern/State");
  auto state = scene.channels_of("state", "tern/State");
  CHECK(names(state) == std::vector<std::string>{"/tf", "/tern/markers/aircraft", "/tern/markers/track"});
  msg::State t, e;
  t.origin_valid = e.origin_valid = true;
  t.origin_lat = e.origin_lat = 47.0;
  t.origin_lon = 8.0;
  e.origin_lon = 8.0 + 1e-4;  // ~7.6 m east
  std::vector<std::string> out;
  truth[0].encode(&t, out);
  state[0].encode(&e, out);
  REQUIRE(out.size() == 2);
  CHECK(contains(out[1], "map_estimate"));
  CHECK(contains(out[1], "base_link_estimate"));
  double x = 0;  // the first transform's translation x (east): after the header, count, stamp, "map", "map_estimate"
  const std::size_t at = out[1].find(std::string("map_estimate\0", 13)) + 13;
  std::memcpy(&x, out[1].data() + (at - 4 + 7) / 8 * 8 + 4, 8);  // aligned to 8 from the end of the 4-byte header
  CHECK(x == doctest::Approx(1e-4 * kRadPerDeg * 6378137.0 * std::cos(47.0 * kRadPerDeg)).epsilon(0.01));
  CHECK_THROWS(scene_options("/nonexistent/aircraft.yaml", ""));
}
