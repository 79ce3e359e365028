// What a ground station is shown (mavlink/telemetry.hpp): NAV_CONTROLLER_OUTPUT's errors, the
// mission's state, the landed state, the wind, from snapshots built by hand.
#include <cmath>

#include <doctest/doctest.h>

#include "mavlink/telemetry.hpp"
#include "tern/math.hpp"

using namespace tern;
using namespace tern::core::mavlink;

namespace {

Snapshot flying_east() {
  Snapshot s;
  s.any = true;
  s.t = 12'345'000'000;
  s.has_state = s.has_command = s.has_internals = s.has_path = s.has_phase = true;
  s.state.valid = s.state.origin_valid = true;
  s.state.p_n = 10.0;  // 10 m north of a line flown east through the origin
  s.state.p_e = 50.0;
  s.state.p_d = -95.0;
  s.state.Va = 24.0;
  s.command.Va_c = 25.0;
  s.command.h_c = 100.0;
  s.command.chi_c = kPi / 2;
  s.internals.phi_c = 10.0 * kRadPerDeg;
  s.internals.theta_c = -2.0 * kRadPerDeg;
  s.path.path_type = msg::CurrentPath::line;
  s.path.r = Eigen::Vector3d::Zero();
  s.path.q = Eigen::Vector3d::UnitY();
  s.path.waypoint_index = 1;
  s.phase.phase = msg::Phase::cruise;
  s.mission_items = 4;
  msg::Waypoint w;
  w.w = Eigen::Vector3d(0.0, 350.0, -100.0);
  s.target = w;
  return s;
}

}  // namespace

TEST_CASE("NAV_CONTROLLER_OUTPUT: commands less the estimate, the path's lateral error, the waypoint's bearing and distance") {
  Snapshot s = flying_east();
  std::optional<GeoOrigin> origin;
  const auto m = nav_controller(s, origin);
  REQUIRE(m.has_value());
  CHECK(m->nav_roll == doctest::Approx(10.0));
  CHECK(m->nav_pitch == doctest::Approx(-2.0));
  CHECK(m->nav_bearing == 90);
  CHECK(m->alt_error == doctest::Approx(5.0));
  CHECK(m->aspd_error == doctest::Approx(1.0));
  CHECK(m->xtrack_error == doctest::Approx(-10.0));  // north of a line flown east: left of it
  CHECK(m->wp_dist == 300);                          // hypot(10, 300) rounds to 300
  CHECK(m->target_bearing == 91);                    // a little south of east, whole degrees

  s.command.override_phi = true;
  s.command.phi_c = -20.0 * kRadPerDeg;
  CHECK(nav_controller(s, origin)->nav_roll == doctest::Approx(-20.0));

  s.path.path_type = msg::CurrentPath::orbit;  // outside an orbit of 40 m about (0, 20)
  s.path.c = Eigen::Vector3d(0.0, 20.0, -100.0);
  s.path.rho = 20.0;
  CHECK(nav_controller(s, origin)->xtrack_error == doctest::Approx(std::hypot(10.0, 30.0) - 20.0));

  s.has_internals = false;
  CHECK_FALSE(nav_controller(s, origin).has_value());
}

TEST_CASE("MISSION_CURRENT and EXTENDED_SYS_STATE follow the phase and the pilot") {
  Snapshot s = flying_east();
  auto m = mission_current(s);
  REQUIRE(m.has_value());
  CHECK(m->seq == 1);
  CHECK(m->total == 4);
  CHECK(m->mission_state == MISSION_STATE_ACTIVE);
  CHECK(m->mission_mode == 1);
  CHECK(extended_sys_state(s)->landed_state == MAV_LANDED_STATE_IN_AIR);

  s.phase.phase = msg::Phase::preflight;
  CHECK(mission_current(s)->mission_state == MISSION_STATE_NOT_STARTED);
  CHECK(extended_sys_state(s)->landed_state == MAV_LANDED_STATE_ON_GROUND);
  s.phase.phase = msg::Phase::flare;
  CHECK(extended_sys_state(s)->landed_state == MAV_LANDED_STATE_LANDING);
  s.phase.phase = msg::Phase::takeoff;
  CHECK(extended_sys_state(s)->landed_state == MAV_LANDED_STATE_TAKEOFF);
  s.phase.phase = msg::Phase::stopped;
  CHECK(mission_current(s)->mission_state == MISSION_STATE_COMPLETE);

  s.has_rc = true;
  s.rc.rc_override = true;
  CHECK(mission_current(s)->mission_mode == 2);
  s.mission_items = 0;
  CHECK(mission_current(s)->mission_state == MISSION_STATE_NO_MISSION);
  s.mission_items.reset();
  CHECK_FALSE(mission_current(s).has_value());
}

TEST_CASE("WIND_COV: the estimate's wind and its accuracy; what tern does not estimate is NaN") {
  Snapshot s = flying_east();
  s.state.w_n = 3.0;
  s.state.w_e = -4.0;
  s.state.origin_alt = 400.0;
  s.state.P_diag[msg::State::P_wind] = 0.09;
  s.state.P_diag[msg::State::P_wind + 1] = 0.16;
  const auto m = wind_cov(s);
  REQUIRE(m.has_value());
  CHECK(m->wind_x == doctest::Approx(3.0));
  CHECK(m->wind_y == doctest::Approx(-4.0));
  CHECK(std::isnan(m->wind_z));
  CHECK(m->wind_alt == doctest::Approx(495.0));
  CHECK(m->horiz_accuracy == doctest::Approx(0.5));
  CHECK(m->time_usec == 12'345'000u);
  s.state.valid = false;
  CHECK_FALSE(wind_cov(s).has_value());
}
