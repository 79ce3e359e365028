// Tests of @NAME@: the complementary filter alone (initial attitude, convergence, coordinated
// turn, GNSS, airspeed) and the plugin through the SDK harness.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "complementary_filter.hpp"
#include "plugin.hpp"
#include "tern/math.hpp"
#include "tern/reflect.hpp"
#include "tern/testing/harness.hpp"

using namespace tern_@NAME@;

namespace {
constexpr double g = 9.81;
// Specific force at rest with attitude (phi, theta): -g_body.
Eigen::Vector3d at_rest(double phi, double theta) {
  return -g * Eigen::Vector3d(-std::sin(theta), std::sin(phi) * std::cos(theta), std::cos(phi) * std::cos(theta));
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

TEST_CASE("filter: the first IMU sample sets roll and pitch; it converges from a wrong attitude") {
  ComplementaryFilter f;
  f.imu(0.0, at_rest(0.3, 0.1), Eigen::Vector3d::Zero());
  CHECK(f.estimate().phi == doctest::Approx(0.3));
  CHECK(f.estimate().theta == doctest::Approx(0.1));
  f.reset();
  f.imu(0.0, at_rest(0.0, 0.0), Eigen::Vector3d::Zero());
  for (int i = 1; i <= 4000; ++i) f.imu(i * 0.0025, at_rest(-0.4, 0.2), Eigen::Vector3d::Zero());  // 10 s = 5 tau
  CHECK(f.estimate().phi == doctest::Approx(-0.4).epsilon(0.01));
  CHECK(f.estimate().theta == doctest::Approx(0.2).epsilon(0.01));
}

TEST_CASE("filter: holds the bank of a coordinated turn (centripetal term removed)") {
  // Level turn at Va = 17 m/s, phi = 0.3: psi' = g tan(phi) / Va, q = psi' sin(phi), r = psi' cos(phi).
  const double Va = 17.0, phi = 0.3, psi_dot = g * std::tan(phi) / Va;
  const Eigen::Vector3d gyro(0.0, psi_dot * std::sin(phi), psi_dot * std::cos(phi));
  const Eigen::Vector3d accel = gyro.cross(Eigen::Vector3d(Va, 0, 0)) + at_rest(phi, 0.0);
  ComplementaryFilter f;
  f.airspeed(0.5 * 1.225 * Va * Va, 1.225);
  CHECK(f.estimate().Va == doctest::Approx(Va));
  f.imu(0.0, accel, gyro);
  for (int i = 1; i <= 8000; ++i) f.imu(i * 0.0025, accel, gyro);  // 20 s
  CHECK(f.estimate().phi == doctest::Approx(phi).epsilon(0.01));
  CHECK(std::fabs(f.estimate().theta) < 0.01);
  // heading integrates the turn rate: 20 s at psi' (wrapped)
  CHECK(std::fabs(tern::wrap_pi(f.estimate().psi - 20.0 * psi_dot)) < 0.02);
}

TEST_CASE("filter: GNSS position, velocity and heading from the course") {
  ComplementaryFilter f;
  f.imu(0.0, at_rest(0, 0), Eigen::Vector3d::Zero());
  f.gnss({100, 50, -80}, {0, 15, 0});  // flying east
  CHECK(f.estimate().position_valid);
  CHECK(f.estimate().p_n == 100.0);
  CHECK(f.estimate().psi == doctest::Approx(1.5708).epsilon(1e-4));
  for (int i = 1; i <= 40; ++i) f.imu(i * 0.0025, at_rest(0, 0), Eigen::Vector3d::Zero());  // 0.1 s
  CHECK(f.estimate().p_e == doctest::Approx(51.5));  // dead reckoning at 15 m/s
  f.gnss({100, 53.5, -80}, {0, 15, 0});
  CHECK(f.estimate().p_e == doctest::Approx(52.5));  // blended half way (gnss_blend 0.5)
}

TEST_CASE("flat earth: 0.001 deg of latitude is about 111 m; altitude up is p_d down") {
  const Eigen::Vector3d p = geodetic_to_ned(40.001, -111.0, 1400.0, 40.0, -111.0, 1387.0);
  CHECK(p.x() == doctest::Approx(111.0).epsilon(0.01));
  CHECK(p.y() == doctest::Approx(0.0));
  CHECK(p.z() == doctest::Approx(-13.0));
  CHECK(geodetic_to_ned(40.0, -110.999, 1387.0, 40.0, -111.0, 1387.0).y() == doctest::Approx(85.3).epsilon(0.01));
}

TEST_CASE("plugin: state from imu and gnss; valid after the first 3-D fix; origin modes") {
  tern::msg::Imu imu;
  imu.accel = at_rest(0.0, 0.0);
  tern::msg::Gnss fix;
  fix.fix_type = tern::msg::FixType::fix_2d;
  fix.lat = 40.2473724;  // 0.001 deg north of the default fixed origin
  fix.lon = -111.6474138;
  fix.alt = 1487.0;
  fix.vel = {17.0, 0.0, 0.0};
  for (const char* mode : {"first_fix", "fixed"}) {
    tern::testing::Harness h(std::make_unique<@CLASS@>(), {{"origin_mode", std::string(mode)}});
    h.set_input("imu", imu);
    h.set_input("gnss", fix);
    h.step(tern::from_seconds(0.0025));
    CHECK_FALSE(h.output<tern::msg::State>("state").valid);  // 2-D fix: ignored
    fix.fix_type = tern::msg::FixType::fix_3d;
    imu.stamp = tern::from_seconds(0.005);
    h.set_input("imu", imu);
    h.set_input("gnss", fix);
    h.step(tern::from_seconds(0.005));
    const auto& s = h.output<tern::msg::State>("state");
    CHECK(s.valid);
    CHECK(s.origin_valid);
    CHECK(s.chi == doctest::Approx(0.0));
    CHECK(s.Vg == doctest::Approx(17.0));
    if (std::string(mode) == "fixed") {
      CHECK(s.p_n == doctest::Approx(111.0).epsilon(0.01));
      CHECK(s.altitude() == doctest::Approx(100.0));
    } else {
      CHECK(s.p_n == 0.0);
      CHECK(s.origin_alt == 1487.0);
    }
    fix.fix_type = tern::msg::FixType::fix_2d;
  }
  CHECK_THROWS_AS(tern::testing::Harness(std::make_unique<@CLASS@>(), {{"origin_mode", std::string("gps")}}), tern::ParamError);
}

TEST_CASE("plugin: after reset() a flight is the first one again, bit for bit") {
  // The contract of tern/plugin.hpp: what a flight changes lives in @CLASS@::Flight, which
  // reset() replaces. Two flights of the same inputs with a reset() between them must publish
  // the same states; a field kept outside Flight (the filter's estimate, the origin) would carry
  // the first flight into the second and fail this.
  tern::testing::Harness h(std::make_unique<@CLASS@>());
  auto fly = [&h] {
    std::vector<std::vector<unsigned char>> published;
    for (int i = 1; i <= 400; ++i) {  // 1 s of IMU at 400 Hz, airspeed and air data with each sample
      tern::msg::Imu imu;
      imu.stamp = tern::from_seconds(0.0025 * i);
      imu.accel = at_rest(0.1, 0.05);
      imu.gyro = {0.01, 0.0, 0.02};
      h.set_input("imu", imu);
      tern::msg::DiffPressure dp;
      dp.pressure = 150.0;
      h.set_input("diff_pressure", dp);
      tern::msg::Baro baro;
      baro.pressure = 85000.0;
      baro.temperature = 280.0;
      h.set_input("baro", baro);
      if (i % 40 == 1) {  // GNSS at 10 Hz, flying north at 17 m/s: a 2-D fix first (no origin yet), then 3-D
        tern::msg::Gnss fix;
        fix.fix_type = i == 1 ? tern::msg::FixType::fix_2d : tern::msg::FixType::fix_3d;
        fix.lat = 40.2463724 + 1.53e-4 * 0.0025 * i;
        fix.lon = -111.6474138;
        fix.alt = 1487.0;
        fix.vel = {17.0, 0.0, 0.0};
        h.set_input("gnss", fix);
      }
      h.step(imu.stamp);
      published.push_back(logged(h.output<tern::msg::State>("state")));
    }
    return published;
  };
  const auto first = fly();
  h.reset();
  const auto second = fly();
  REQUIRE(second.size() == first.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    CAPTURE(i);
    REQUIRE(second[i] == first[i]);
  }
}
