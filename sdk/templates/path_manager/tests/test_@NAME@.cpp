// Tests of @NAME@: the line manager alone (switching half planes, loop, end of mission) and
// the plugin through the SDK harness.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "line_manager.hpp"
#include "plugin.hpp"
#include "tern/reflect.hpp"
#include "tern/testing/harness.hpp"

using tern_@NAME@::LineManager;
using tern_@NAME@::Segment;

namespace {
// A square: 0 -> 1 north 200 m, 1 -> 2 east, 2 -> 3 south, altitude 100 m.
std::vector<Eigen::Vector3d> square() {
  return {{0, 0, -100}, {200, 0, -100}, {200, 200, -100}, {0, 200, -100}};
}

/// What the flight log records of a message: the bytes of every field its describe() names.
template <class M>
std::vector<unsigned char> logged(const M& m) {
  std::vector<unsigned char> bytes;
  for (const tern::reflect::Column& c : tern::reflect::layout<M>()) {
    const auto* p = reinterpret_cast<const unsigned char*>(&m) + c.offset;
    bytes.insert(bytes.end(), p, p + tern::reflect::scalar_size(c.kind));
  }
  return bytes;
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

TEST_CASE("plugin: after reset() a flight is the first one again, bit for bit") {
  // The contract of tern/plugin.hpp: what a flight changes lives in @CLASS@::Flight, which
  // reset() replaces. Two flights of the same inputs with a reset() between them must publish
  // the same paths; a field kept outside Flight (the segment flown, the list's revision, the
  // waypoints' airspeeds) would carry the first flight into the second and fail this.
  tern::testing::Harness h(std::make_unique<@CLASS@>());
  tern::msg::WaypointList list;
  list.revision = 1;
  list.count = 4;
  for (std::size_t k = 0; k < 4; ++k) list.items[k].w = square()[k];
  list.items[2].Va_d = 20.0;
  auto fly = [&] {
    std::vector<std::vector<unsigned char>> published;  // per step: the path, empty if none
    for (int i = 1; i <= 60; ++i) {  // up the first side and along the second; no state for 1 s
      tern::msg::State x;
      x.valid = i > 5;
      x.p_n = std::min(10.0 * i, 200.0);
      x.p_e = std::max(10.0 * i - 200.0, 0.0);
      x.p_d = -100.0;
      h.set_input("waypoints", list);
      h.set_input("state", x);
      const auto before = h.published("current_path");
      h.step(tern::from_seconds(0.2 * i));
      published.push_back(h.published("current_path") > before ? logged(h.output<tern::msg::CurrentPath>("current_path"))
                                                               : std::vector<unsigned char>{});
    }
    return published;
  };
  const auto first = fly();
  CHECK(first.back().size() > 0);
  CHECK(h.output<tern::msg::CurrentPath>("current_path").waypoint_index == 3);  // past w2 by the end
  h.reset();
  const auto second = fly();
  REQUIRE(second.size() == first.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    CAPTURE(i);
    REQUIRE(second[i] == first[i]);
  }
}
