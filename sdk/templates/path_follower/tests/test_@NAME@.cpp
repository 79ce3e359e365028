// Tests of @NAME@: the vector fields alone (converging to a line, orbit tangent, altitude) and
// the plugin through the SDK harness.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <spdlog/sinks/ringbuffer_sink.h>

#include "plugin.hpp"
#include "tern/reflect.hpp"
#include "tern/testing/harness.hpp"
#include "vector_field.hpp"

using namespace tern_@NAME@;

namespace {
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

TEST_CASE("line: a kinematic aircraft converges onto the line and holds it") {
  // Line north through the origin at 100 m altitude; start 200 m east of it, flying east.
  const Eigen::Vector3d r(0, 0, -100), q(1, 0, 0);
  Eigen::Vector3d p(0, 200, -100);
  double chi = 1.5708;
  const double Va = 17.0, dt = 0.01, tau_chi = 1.0;  // course follows chi_c with a 1 s lag
  const FollowerGains g;
  for (int i = 0; i < 12000; ++i) {  // 120 s
    const Guidance u = follow_line(r, q, p, chi, g);
    chi += dt * (u.chi_c - chi) / tau_chi;
    p += dt * Va * Eigen::Vector3d(std::cos(chi), std::sin(chi), 0.0);
  }
  CHECK(std::fabs(cross_track_error(r, q, p)) < 0.5);
  CHECK(std::fabs(chi) < 0.01);  // flying north, along the line
}

TEST_CASE("line: course and altitude commands") {
  const FollowerGains g;
  // On the line: the line's course. Far to its right (east of a north line): chi_inf towards it.
  CHECK(follow_line({0, 0, -50}, {1, 0, 0}, {10, 0, -50}, 0.0, g).chi_c == doctest::Approx(0.0));
  CHECK(follow_line({0, 0, -50}, {1, 0, 0}, {0, 1e6, -50}, 0.0, g).chi_c == doctest::Approx(-g.chi_inf).epsilon(1e-4));
  // Course is unwrapped near the current course: a line to the south seen from chi = 3 rad.
  CHECK(follow_line({0, 0, -50}, {-1, 0, 0}, {0, 0, -50}, 3.0, g).chi_c == doctest::Approx(3.14159265).epsilon(1e-6));
  // A climbing line (1 m up per 10 m north): 100 m along it, 10 m higher (eq. 10.5).
  CHECK(follow_line({0, 0, -50}, {10, 0, -1}, {100, 30, -50}, 0.0, g).h_c == doctest::Approx(60.0));
  CHECK(std::isnan(follow_line({0, 0, 0}, {0, 0, -1}, {0, 0, 0}, 0.0, g).chi_c));  // vertical line
}

TEST_CASE("orbit: tangent on the circle, towards it from outside, feed-forward") {
  const FollowerGains g;
  // Clockwise orbit of radius 100 around the origin, aircraft north of the centre: fly east.
  const Guidance on = follow_orbit({0, 0, -80}, 100.0, 1, {100, 0, -80}, 1.0, 17.0, g);
  CHECK(on.chi_c == doctest::Approx(3.14159265 / 2));
  CHECK(on.h_c == doctest::Approx(80.0));
  CHECK(on.phi_ff == doctest::Approx(std::atan(17.0 * 17.0 / (9.81 * 100.0))));
  // Far outside: heads almost at the centre (course near south from the north).
  const Guidance out = follow_orbit({0, 0, -80}, 100.0, 1, {5000, 0, -80}, 3.0, 17.0, g);
  CHECK(std::fabs(out.chi_c - 3.14159265) < 0.05);
  CHECK(out.phi_ff == 0.0);
}

TEST_CASE("plugin: commands from the path, nothing while the state is invalid") {
  tern::testing::Harness h(std::make_unique<@CLASS@>(), {{"k_path", 0.05}});
  tern::msg::CurrentPath path;
  path.path_type = tern::msg::CurrentPath::line;
  path.Va_d = 18.0;
  path.r = {0, 0, -100};
  path.q = {0, 1, 0};  // east
  tern::msg::State x;
  x.p_d = -90.0;
  x.chi = 1.5;
  h.set_input("state", x);
  h.set_input("current_path", path);
  h.step(tern::from_seconds(0.01));
  CHECK(h.published("controller_command") == 0);
  x.valid = true;
  h.set_input("state", x);
  h.step(tern::from_seconds(0.02));
  REQUIRE(h.published("controller_command") == 1);
  const auto& c = h.output<tern::msg::ControllerCommand>("controller_command");
  CHECK(c.Va_c == 18.0);
  CHECK(c.h_c == doctest::Approx(100.0));
  CHECK(c.chi_c == doctest::Approx(3.14159265 / 2));
  CHECK(c.stamp == tern::from_seconds(0.02));
  CHECK_THROWS_AS(h.set_param("chi_inf", 2.0), tern::ParamError);
}

TEST_CASE("plugin: after reset() a flight is the first one again, commands and warnings") {
  // The contract of tern/plugin.hpp: what a flight changes lives in @CLASS@::Flight, which
  // reset() replaces. Two flights of the same inputs with a reset() between them must publish
  // the same commands and log the same warnings; a "warned once" flag kept outside Flight would
  // silence the second flight's warning and fail this.
  tern::testing::HarnessOptions options;
  options.instance = "follower_reset";  // a logger of its own, to read its lines
  tern::testing::Harness h(std::make_unique<@CLASS@>(), {}, options);
  auto sink = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(64);  // keeps the last 64 lines
  sink->set_pattern("%l %v");
  h.logger()->sinks().push_back(sink);
  struct Flown {
    std::vector<std::vector<unsigned char>> published;  ///< per step: the command, empty if none
    std::vector<std::string> log;                       ///< the lines logged
  };
  auto fly = [&] {
    Flown f;
    const std::size_t logged_before = sink->last_formatted().size();
    for (int i = 1; i <= 100; ++i) {  // 1 s east along a north line, 30 m off; its direction lost twice
      tern::msg::State x;
      x.valid = true;
      x.p_n = 0.17 * i;
      x.p_e = 30.0;
      x.p_d = -100.0;
      x.Va = 17.0;
      tern::msg::CurrentPath path;
      path.path_type = tern::msg::CurrentPath::line;
      path.Va_d = 17.0;
      path.r = {0, 0, -100};
      const bool degenerate = i <= 10 || (i > 50 && i <= 60);
      path.q = {degenerate ? 0.0 : 1.0, 0.0, 0.0};
      h.set_input("state", x);
      h.set_input("current_path", path);
      const auto before = h.published("controller_command");
      h.step(tern::from_seconds(0.01 * i));
      f.published.push_back(h.published("controller_command") > before
                                ? logged(h.output<tern::msg::ControllerCommand>("controller_command"))
                                : std::vector<unsigned char>{});
    }
    const std::vector<std::string> lines = sink->last_formatted();
    f.log.assign(lines.begin() + static_cast<std::ptrdiff_t>(logged_before), lines.end());
    return f;
  };
  const Flown first = fly();
  REQUIRE(first.log.size() == 1);  // once a flight
  CHECK(first.log[0] == "warning current_path is degenerate (zero direction or NaN): command not updated\n");
  h.reset();
  const Flown second = fly();
  CHECK(second.log == first.log);
  REQUIRE(second.published.size() == first.published.size());
  for (std::size_t i = 0; i < first.published.size(); ++i) {
    CAPTURE(i);
    REQUIRE(second.published[i] == first.published[i]);
  }
}
