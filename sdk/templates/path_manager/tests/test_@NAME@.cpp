// Tests of @NAME@: the line manager alone (switching half planes, loop, end of mission) and
// the plugin through the SDK harness.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <memory>

#include "line_manager.hpp"
#include "plugin.hpp"
#include "tern/testing/harness.hpp"

using tern_@NAME@::LineManager;
using tern_@NAME@::Segment;

namespace {
// A square: 0 -> 1 north 200 m, 1 -> 2 east, 2 -> 3 south, altitude 100 m.
std::vector<Eigen::Vector3d> square() {
  return {{0, 0, -100}, {200, 0, -100}, {200, 200, -100}, {0, 200, -100}};
}
}  // namespace

TEST_CASE("manager: follows w0 -> w1 and switches on the bisector half plane at w1") {
  LineManager m;
  m.set_waypoints(square(), true);
  Segment s = m.update({10, 0, -100});
  CHECK(s.type == Segment::line);
  CHECK(s.index == 1);
  CHECK(s.r.isApprox(Eigen::Vector3d(0, 0, -100)));
  CHECK(s.q.isApprox(Eigen::Vector3d(1, 0, 0)));
  // n_1 bisects north and east: (1, 1)/sqrt(2). (190, 5) is before the plane, (190, 15) past it.
  CHECK(m.update({190, 5, -100}).index == 1);
  s = m.update({190, 15, -100});
  CHECK(s.index == 2);
  CHECK(s.q.isApprox(Eigen::Vector3d(0, 1, 0)));
}

TEST_CASE("manager: a loop closes with w3 -> w0 and starts again") {
  LineManager m;
  m.set_waypoints(square(), true);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(200, 1, -100), Eigen::Vector3d(199, 200, -100),
                                  Eigen::Vector3d(0, 199, -100)})
    m.update(p);
  const Segment closing = m.update({10, 200, -100});
  CHECK(closing.index == 0);
  CHECK(closing.q.isApprox(Eigen::Vector3d(0, -1, 0)));
  CHECK(m.update({1, 0, -100}).index == 1);  // past w0: w0 -> w1 again
}

TEST_CASE("manager: without a loop it orbits the last waypoint; no waypoints: orbit the origin") {
  LineManager m;
  m.orbit_radius = 60.0;
  m.set_waypoints({{0, 0, -50}, {100, 0, -50}}, false);
  CHECK(m.update({50, 0, -50}).type == Segment::line);
  const Segment s = m.update({101, 0, -50});
  CHECK(s.type == Segment::orbit);
  CHECK(s.c.isApprox(Eigen::Vector3d(100, 0, -50)));
  CHECK(s.rho == 60.0);
  CHECK(m.update({0, 0, -50}).type == Segment::orbit);  // stays done
  m.set_waypoints({}, true);
  CHECK(m.update({0, 0, -50}).c.isApprox(Eigen::Vector3d(0, 0, -m.loiter_altitude)));
  // duplicates dropped: two distinct points remain, a line
  m.set_waypoints({{0, 0, -50}, {0, 0, -50.5}, {100, 0, -50}}, true);
  CHECK(m.update({1, 0, -50}).type == Segment::line);
}

TEST_CASE("plugin: publishes the path once the state is valid; a new revision restarts") {
  tern::testing::Harness h(std::make_unique<@CLASS@>(), {{"default_airspeed", 16.0}});
  tern::msg::WaypointList list;
  list.revision = 1;
  list.count = 3;
  list.items[0].w = {0, 0, -100};
  list.items[1].w = {300, 0, -100};
  list.items[1].Va_d = 20.0;
  list.items[2].w = {300, 300, -100};
  tern::msg::State x;
  x.p_n = 10.0;
  x.p_d = -100.0;
  h.set_input("waypoints", list);
  h.set_input("state", x);
  h.step(tern::from_seconds(0.01));
  CHECK(h.published("current_path") == 0);
  x.valid = true;
  h.set_input("state", x);
  h.step(tern::from_seconds(0.02));
  const auto& path = h.output<tern::msg::CurrentPath>("current_path");
  CHECK(path.path_type == tern::msg::CurrentPath::line);
  CHECK(path.waypoint_index == 1);
  CHECK(path.Va_d == 20.0);
  x.p_n = 299.0;
  x.p_e = 50.0;  // past the switching plane at w1
  h.set_input("state", x);
  h.step(tern::from_seconds(0.03));
  CHECK(h.output<tern::msg::CurrentPath>("current_path").waypoint_index == 2);
  CHECK(h.output<tern::msg::CurrentPath>("current_path").Va_d == 16.0);  // default: w2 has none
  list.revision = 2;
  h.set_input("waypoints", list);
  x.p_n = 10.0;
  x.p_e = 0.0;
  h.set_input("state", x);
  h.step(tern::from_seconds(0.04));
  CHECK(h.output<tern::msg::CurrentPath>("current_path").waypoint_index == 1);
}
