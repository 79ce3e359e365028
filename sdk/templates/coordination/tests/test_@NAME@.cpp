// Tests of @NAME@: the geometry alone and the plugin through the SDK harness with three vehicles.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gather.hpp"
#include "plugin.hpp"
#include "tern/geodesy.hpp"
#include "tern/testing/harness.hpp"

namespace {
const std::vector<double> kOrigin = {45.0, 7.0, 300.0};
const tern::GeoOrigin kCommon(kOrigin[0], kOrigin[1], kOrigin[2]);

tern::testing::HarnessOptions fleet() {
  tern::testing::HarnessOptions o;
  o.vehicles = {"uav1", "uav2", "uav3"};
  return o;
}

/// Vehicle i's estimate at `ned` (common frame), in its own frame about its own origin.
tern::msg::State state_at(std::size_t i, const Eigen::Vector3d& ned) {
  const tern::GeoPoint o = kCommon.to_geodetic(Eigen::Vector3d(500.0 * i, -700.0 * i, 0.0));
  const Eigen::Vector3d own = tern::GeoOrigin(o).to_ned(kCommon.to_geodetic(ned));
  tern::msg::State x;
  x.valid = x.origin_valid = true;
  x.origin_lat = o.lat;
  x.origin_lon = o.lon;
  x.origin_alt = o.alt;
  x.p_n = own.x();
  x.p_e = own.y();
  x.p_d = own.z();
  return x;
}

std::map<std::string, double> summary_of(tern::Plugin& p) {
  std::map<std::string, double> m;
  for (const auto& [k, v] : p.summary()) m[k] = v;
  return m;
}
}  // namespace

TEST_CASE("gather: slots stack upwards, arrival is horizontal, separation is the closest pair") {
  const Eigen::Vector3d point(10, 20, -100);
  CHECK(tern_@NAME@::slot(point, 2, 15.0).isApprox(Eigen::Vector3d(10, 20, -130)));
  CHECK(tern_@NAME@::within({60, 20, -300}, point, 50.0));
  CHECK_FALSE(tern_@NAME@::within({61, 20, -100}, point, 50.0));
  tern_@NAME@::Separation s;
  CHECK(s.min() == 0.0);
  s.add({{0, 0, 0}, {30, 40, 0}, {0, 0, 200}});
  s.add({{0, 0, 0}, {NAN, 0, 0}, {0, 0, 20}});  // the NaN one is left out
  CHECK(s.min() == doctest::Approx(20.0));
}

TEST_CASE("plugin: sends each valid vehicle its slot, as lat/lon/alt, and records arrivals") {
  tern::testing::Harness h(std::make_unique<@CLASS@>(),
                           {{"origin", kOrigin}, {"point", std::vector<double>{0.0, 0.0, -100.0}}, {"altitude_spacing", 25.0}}, fleet());
  h.set_input("uav1/state", state_at(0, {-900, 0, -80}));
  h.set_input("uav2/state", state_at(1, {0, 60, -90}));  // already over the point
  tern::msg::State late = state_at(2, {900, 0, -80});
  late.valid = false;  // not initialised yet: waited for
  h.set_input("uav3/state", late);
  h.step(tern::from_seconds(1.0));
  CHECK(h.published("uav1/mission_edit") == 1);
  CHECK(h.published("uav3/mission_edit") == 0);
  const tern::msg::MissionEdit& e = h.output<tern::msg::MissionEdit>("uav2/mission_edit");
  CHECK(e.set_current_wp);
  CHECK(e.waypoint.lla);
  CHECK(e.waypoint.type == tern::msg::Waypoint::loiter);
  const Eigen::Vector3d at = kCommon.to_ned(tern::GeoPoint{e.waypoint.w.x(), e.waypoint.w.y(), e.waypoint.w.z()});
  CHECK((at - Eigen::Vector3d(0, 0, -125)).norm() < 0.01);  // vehicle 1 of 0..2: 25 m above
  h.set_input("uav3/state", state_at(2, {900, 0, -80}));
  h.step(tern::from_seconds(2.0));
  CHECK(h.published("uav3/mission_edit") == 1);
  CHECK(h.published("uav1/mission_edit") == 1);  // sent once
  h.stop();
  const auto s = summary_of(h.plugin());
  CHECK(s.at("arrival_uav2") == 1.0);
  CHECK(s.at("arrival_uav1") == -1.0);
  CHECK(s.at("vehicles_arrived") == 1.0);
  CHECK(s.at("min_separation") == doctest::Approx(std::sqrt(900.0 * 900.0 + 60.0 * 60.0 + 10.0 * 10.0)).epsilon(1e-6));
}

TEST_CASE("plugin: after reset() a flight is the first one again") {
  // The contract of tern/plugin.hpp: what a flight changes lives in @CLASS@::Flight, which
  // reset() replaces. Two flights with a reset() between them must give the same summary and
  // send the same edits; a flag kept outside Flight would leave the second flight's vehicles unsent.
  tern::testing::Harness h(std::make_unique<@CLASS@>(), {{"origin", kOrigin}, {"loiter_radius", 85.0}}, fleet());
  auto fly = [&h] {
    for (int s = 1; s <= 100; ++s) {
      for (std::size_t i = 0; i < 3; ++i)
        h.set_input("uav" + std::to_string(i + 1) + "/state", state_at(i, {-1000.0 + 10.0 * s, 50.0 * i, -100.0}));
      h.step(tern::from_seconds(0.5 * s));
    }
    h.stop();
    return std::make_pair(summary_of(h.plugin()), h.published("uav1/mission_edit"));
  };
  const auto first = fly();
  CHECK(first.first.at("vehicles_arrived") == 2.0);  // uav1 and uav2 pass within 85 m, uav3 100 m off
  CHECK(first.first.at("arrival_uav1") == doctest::Approx(46.0));  // -1000 + 10 s = -80 (85 m: inside) at s = 92
  CHECK(first.second == 1);
  h.reset();
  const auto second = fly();
  CHECK(second.first == first.first);
  CHECK(second.second == 1);  // the harness empties the outputs: one edit again
}
