// The failsafes (core/host/safety/failsafe.hpp) and their config section alone: no plugin, no host.
#include <doctest/doctest.h>

#include <yaml-cpp/yaml.h>

#include "config/error.hpp"
#include "safety/failsafe.hpp"
#include "config/failsafe_config.hpp"

using namespace tern;
using namespace tern::core;

namespace {

constexpr Nanos kTick = 10'000'000;  // 100 Hz

msg::State at(double n, double e, double h) {
  msg::State s;
  s.valid = true;
  s.status = msg::StateStatus::ok;
  s.p_n = n;
  s.p_e = e;
  s.p_d = -h;
  return s;
}

// A monitor with what it saw last: the last fix and when the link was last heard.
struct Watch {
  explicit Watch(const FailsafeConfig& c = {}) { m.set_config(c); }
  FailsafeMonitor m;
  std::optional<Nanos> fix, heard;
  // Runs from t0 to t1 (s) with `s`, fixes until `fix_until` and the link heard until
  // `heard_until` (s); returns the events.
  std::vector<FailsafeEvent> run(double t0, double t1, const msg::State& s, double fix_until, double heard_until = -1.0,
                                 bool airborne = true, bool landing = false) {
    std::vector<FailsafeEvent> all;
    for (Nanos t = from_seconds(t0); t <= from_seconds(t1); t += kTick) {
      if (to_seconds(t) <= fix_until) fix = t;
      if (to_seconds(t) <= heard_until) heard = t;
      for (auto& e : m.check({t, airborne, &s, fix, heard, landing})) all.push_back(e);
    }
    return all;
  }
};

FailsafeConfig parse(const std::string& yaml) { return parse_failsafes(YAML::Load(yaml), "cfg.yaml"); }

std::string error_of(const std::string& yaml) {
  try {
    parse(yaml);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("failsafe: GNSS silent beyond its timeout -> loiter at the estimate of that moment, once; back -> said, no new action") {
  Watch m;
  const msg::State s = at(120.0, -40.0, 70.0);
  auto ev = m.run(0.0, 10.5, s, 5.0);  // last fix at 5 s, timeout 5 s
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].cause == "gnss_loss");
  CHECK(ev[0].action == "loiter");
  CHECK(to_seconds(ev[0].t) == doctest::Approx(10.01).epsilon(0.002));  // silent > 5 s
  CHECK(ev[0].centre == Eigen::Vector3d(120.0, -40.0, -70.0));
  CHECK(ev[0].detail.find("no valid GNSS fix for 5.0 s") != std::string::npos);
  ev = m.run(10.51, 30.0, s, 5.0);
  CHECK(ev.empty());  // engaged once
  ev = m.run(30.01, 31.0, s, 31.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].cause == "gnss_back");
  CHECK(ev[0].action == "none");
}

TEST_CASE("failsafe: GNSS degraded in the estimate for the timeout engages too; nothing on the ground or before a first fix") {
  Watch m;
  msg::State s = at(0.0, 0.0, 70.0);
  s.degraded_sensors = msg::sensor_bit::gnss;
  auto ev = m.run(0.0, 4.9, s, 10.0);
  CHECK(ev.empty());
  ev = m.run(4.91, 5.2, s, 10.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].detail.find("degraded") != std::string::npos);
  Watch ground;
  CHECK(ground.run(0.0, 20.0, at(0, 0, 0), 1.0, -1.0, false).empty());
  Watch never;
  CHECK(never.run(0.0, 20.0, at(0, 0, 70), -1.0).empty());
}

TEST_CASE("failsafe: a ground station heard, then silent -> return home at the set altitude; termination after terminate_after") {
  FailsafeConfig c;
  c.link_loss.enabled = true;
  c.link_loss.altitude = 90.0;
  c.link_loss.terminate_after = 20.0;
  c.link_loss.terminate_action = TerminateAction::spin;
  Watch m(c);
  CHECK(m.run(0.0, 60.0, at(300, 200, 70), 100.0, -1.0).empty());  // never heard: no link to lose
  Watch lost(c);
  auto ev = lost.run(0.0, 60.0, at(300, 200, 70), 100.0, 3.0);
  REQUIRE(ev.size() == 2);
  CHECK(ev[0].cause == "link_loss");
  CHECK(ev[0].action == "return_home");
  CHECK(to_seconds(ev[0].t) == doctest::Approx(13.01).epsilon(0.002));
  CHECK(ev[0].centre == Eigen::Vector3d(0.0, 0.0, -90.0));
  CHECK(ev[1].cause == "terminate");
  CHECK(to_seconds(ev[1].t - ev[0].t) == doctest::Approx(20.0).epsilon(0.001));
  CHECK(ev[1].terminate == TerminateAction::spin);
  const msg::Actuators cmd = termination_command(TerminateAction::spin, 0.7);
  CHECK(cmd.delta_t == 0.0);
  CHECK(cmd.delta_e == -0.7);  // trailing edge up
  CHECK(termination_command(TerminateAction::glide, 0.7).delta_e == 0.0);
}

TEST_CASE("failsafe: the link heard again before the termination -> link_back, and no termination") {
  FailsafeConfig c;
  c.link_loss.enabled = true;
  c.link_loss.terminate_after = 20.0;
  Watch m(c);
  auto ev = m.run(0.0, 20.0, at(10, 10, 60), 100.0, 3.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].centre.z() == doctest::Approx(-60.0));  // no altitude set: the altitude at the loss
  ev = m.run(20.01, 60.0, at(10, 10, 60), 100.0, 60.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].cause == "link_back");
}

TEST_CASE("failsafe: geofence: distance, altitudes and polygon each breach; the loiter altitude is clamped inside") {
  FailsafeConfig c = parse("geofence: {max_distance: 400, min_altitude: 20, max_altitude: 150, altitude_margin: 10}");
  Watch m(c);
  CHECK(m.run(0.0, 1.0, at(100, 100, 10), 100.0).empty());  // below min_altitude, never above it yet
  CHECK(m.run(1.01, 2.0, at(100, 100, 70), 100.0).empty());
  auto ev = m.run(2.01, 2.02, at(350, 250, 160), 100.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].cause == "geofence");
  CHECK(ev[0].action == "return_home");
  CHECK(ev[0].detail.find("beyond max_distance 400 m") != std::string::npos);
  CHECK(ev[0].centre == Eigen::Vector3d(0.0, 0.0, -140.0));  // 160 m clamped to 150 - 10
  ev = m.run(2.03, 3.0, at(100, 0, 100), 100.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].cause == "geofence_inside");
  ev = m.run(3.01, 3.02, at(100, 0, 15), 100.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].detail.find("below min_altitude 20 m") != std::string::npos);
  CHECK(ev[0].centre.z() == doctest::Approx(-30.0));
  Watch poly(parse("geofence: {polygon: [[100, -100], [100, 100], [-100, 100], [-100, -100]]}"));
  // the final approach and the flare descend through the floor (issue 46): no breach there, nor
  // in the go-around's climb back through it; once above it again, the floor holds
  Watch landing(c);
  CHECK(landing.run(0.0, 1.0, at(100, 100, 70), 100.0).empty());
  CHECK(landing.run(1.01, 2.0, at(100, 100, 5), 100.0, -1.0, true, true).empty());
  CHECK(landing.run(2.01, 3.0, at(100, 100, 5), 100.0).empty());
  CHECK(landing.run(3.01, 4.0, at(100, 100, 40), 100.0).empty());
  ev = landing.run(4.01, 4.02, at(100, 100, 5), 100.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].detail.find("below min_altitude 20 m") != std::string::npos);
  CHECK(poly.run(0.0, 1.0, at(90, 90, 50), 100.0).empty());
  ev = poly.run(1.01, 1.02, at(90, 110, 50), 100.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].detail.find("outside the fence's zones") != std::string::npos);
}

TEST_CASE("failsafe config: defaults, and one line naming the field and value for bad input") {
  const FailsafeConfig d = parse_failsafes(YAML::Node(), "cfg.yaml");
  CHECK(d.gnss_loss.enabled);
  CHECK(d.gnss_loss.timeout == 5.0);
  CHECK_FALSE(d.link_loss.enabled);  // off unless the config gives the section
  CHECK(d.link_loss.timeout == 10.0);
  CHECK_FALSE(d.link_loss.terminate_after);
  CHECK_FALSE(d.geofence.enabled);
  const FailsafeConfig c = parse("gnss_loss: {enabled: false}\nlink_loss: {timeout: 3, terminate: {after: 120, action: spin}}");
  CHECK_FALSE(c.gnss_loss.enabled);
  CHECK(c.link_loss.enabled);  // the section given
  CHECK(c.link_loss.timeout == 3.0);
  CHECK(*c.link_loss.terminate_after == 120.0);
  CHECK(c.link_loss.terminate_action == TerminateAction::spin);
  CHECK(error_of("gnss_loss: {timeout: -1}").find("failsafes.gnss_loss.timeout: -1 s is below 0") != std::string::npos);
  CHECK(error_of("gnss_loss: {timeout: soon}").find("failsafes.gnss_loss.timeout: expected a number (s), got 'soon'") != std::string::npos);
  CHECK(error_of("link_loss: {terminate: {after: 60, action: explode}}")
            .find("failsafes.link_loss.terminate.action: 'explode' is not glide or spin") != std::string::npos);
  CHECK(error_of("link_loss: {terminate: {action: glide}}").find("give after") != std::string::npos);
  CHECK(error_of("geofence: {polygon: [[100, 100], [200, 100], [200, 200]]}").find("home (n 0, e 0) is outside the polygon") !=
        std::string::npos);
  CHECK(error_of("geofence: {polygon: [[1, 2]]}").find("at least 3") != std::string::npos);
  CHECK(error_of("geofence: {min_altitude: 50, max_altitude: 60}").find("less than 2 x altitude_margin") != std::string::npos);
  CHECK(error_of("geofence: {}").find("no limit") != std::string::npos);
  CHECK(error_of("gnss_los: {}").find("unknown key 'gnss_los'") != std::string::npos);
}

TEST_CASE("geofence zones: inside one inclusion group whole, inside no exclusion (common.xml's FENCE rule)") {
  const FenceZone square{true, 0, {{100, -100}, {100, 100}, {-100, 100}, {-100, -100}}, Eigen::Vector2d::Zero(), 0.0};
  const FenceZone circle{true, 0, {}, Eigen::Vector2d(100, 0), 60.0};
  const FenceZone far{true, 1, {}, Eigen::Vector2d(1000, 0), 50.0};
  const FenceZone hole{false, 0, {}, Eigen::Vector2d(0, 50), 20.0};
  CHECK(inside_zones({}, {5000, 5000}));  // no zone: no limit
  CHECK(inside_zones({square}, {90, 90}));
  CHECK_FALSE(inside_zones({square}, {90, 110}));
  // group 0 is the intersection of the square and the circle; group 1 another place
  CHECK(inside_zones({square, circle, far}, {90, 0}));
  CHECK_FALSE(inside_zones({square, circle, far}, {0, 0}));    // in the square, not the circle
  CHECK(inside_zones({square, circle, far}, {1020, 0}));       // group 1 whole
  CHECK_FALSE(inside_zones({square, circle, far}, {500, 0}));  // in no group
  // an exclusion zone alone: everywhere but inside it
  CHECK(inside_zones({hole}, {0, 0}));
  CHECK_FALSE(inside_zones({hole}, {0, 45}));
  CHECK_FALSE(inside_zones({square, hole}, {10, 50}));
}

TEST_CASE("rally points: a return goes to the nearest one the fence allows, or home when home is nearer") {
  const std::vector<Eigen::Vector3d> rally{{400, 0, 80}, {0, 600, 60}, {900, 0, 70}};
  const FenceZone keep_out{false, 0, {}, Eigen::Vector2d(900, 0), 30.0};
  CHECK(nearest_rally(rally, {}, {450, 50}) == std::optional<std::size_t>(0));
  CHECK(nearest_rally(rally, {}, {50, 500}) == std::optional<std::size_t>(1));
  CHECK(nearest_rally(rally, {}, {1000, 0}) == std::optional<std::size_t>(2));
  CHECK(nearest_rally(rally, {keep_out}, {1000, 0}) == std::optional<std::size_t>(0));  // the nearest is fenced off
  CHECK_FALSE(nearest_rally(rally, {}, {100, 100}));                                    // home is nearer
  CHECK_FALSE(nearest_rally({}, {}, {1000, 0}));

  // the link-loss return flies to it at the rally point's altitude
  FailsafeConfig c = parse("link_loss: {timeout: 3, altitude: 90}\nrally: [[400, 0, 80], [0, 600, 60]]");
  Watch m(c);
  auto ev = m.run(0.0, 10.0, at(450, 50, 70), 100.0, 3.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].centre == Eigen::Vector3d(400.0, 0.0, -80.0));
  CHECK(ev[0].detail.find("rally point 0") != std::string::npos);
  Watch near_home(c);
  ev = near_home.run(0.0, 10.0, at(50, 50, 70), 100.0, 3.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].centre == Eigen::Vector3d(0.0, 0.0, -90.0));
}

TEST_CASE("geofence action: report goes on, loiter stays where the breach was, return_home goes to a rally point") {
  FailsafeConfig c = parse("geofence: {max_distance: 400, max_altitude: 150, action: loiter}\nrally: [[350, 0, 200]]");
  Watch loiter(c);
  auto ev = loiter.run(0.0, 0.01, at(410, 0, 160), 100.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].action == "loiter");
  CHECK(ev[0].centre == Eigen::Vector3d(410.0, 0.0, -140.0));
  c.geofence.action = FenceAction::report;
  Watch report(c);
  ev = report.run(0.0, 0.01, at(410, 0, 100), 100.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].action == "report");
  c.geofence.action = FenceAction::return_home;
  Watch back(c);
  ev = back.run(0.0, 0.01, at(410, 0, 100), 100.0);
  REQUIRE(ev.size() == 1);
  CHECK(ev[0].action == "return_home");
  CHECK(ev[0].centre == Eigen::Vector3d(350.0, 0.0, -140.0));  // the rally point's 200 m clamped under max_altitude - margin
  CHECK(error_of("geofence: {max_distance: 400, action: panic}").find("'panic' is not report, loiter or return_home") != std::string::npos);
  CHECK(error_of("rally: [[1, 2]]").find("failsafes.rally[0]: expected [n, e, altitude above home]") != std::string::npos);
  CHECK(error_of("rally: [[1, 2, -5]]").find("failsafes.rally[0][2]: -5 m is below 0") != std::string::npos);
}
