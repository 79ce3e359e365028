// Tests of sim_aero: aircraft files, physics invariants, trim, wind, sensors, determinism (the
// ground: test_ground.cpp; the model at large angles: test_large_angles.cpp).
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "statistics.hpp"
#include "tern/aircraft.hpp"
#include "tern/math.hpp"
#include "tern/aero/model.hpp"
#include "tern_sim_aero/sensors.hpp"
#include "tern_sim_aero/simulator.hpp"
#include "tern/aero/trim.hpp"
#include "tern_sim_aero/wind.hpp"

using tern::Aircraft;
using tern::kGravity;
using tern::load_aircraft;
using tern::parse_aircraft;

using namespace tern::sim;
using tern::sim::test::mean;
using tern::sim::test::stddev;

namespace {
const std::string kData = TERN_SIM_AERO_TEST_DATA;
const std::string kAircraft = TERN_AIRCRAFT_DIR;

Aircraft anaconda() { return load_aircraft(kAircraft + "/anaconda.yaml"); }

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Error message of parse_aircraft on a modified tern document.
std::string load_error(const YAML::Node& doc) {
  try {
    parse_aircraft(doc, "test.yaml");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}

// An aircraft with (practically) no air: no aerodynamic or propeller force.
Aircraft vacuum() {
  Aircraft ac = anaconda();
  ac.rho = 1e-30;
  return ac;
}
}  // namespace

// ---------------------------------------------------------------- aircraft files -------------

TEST_CASE("aircraft: tern's anaconda.yaml is the ROSflight Anaconda file, value for value") {
  const Aircraft t = anaconda();
  const Aircraft r = load_aircraft(kData + "/anaconda_dynamics.yaml");
  CHECK(t.mass == r.mass);
  CHECK(t.Jx == r.Jx);
  CHECK(t.Jy == r.Jy);
  CHECK(t.Jz == r.Jz);
  CHECK(t.Jxz == r.Jxz);
  CHECK(t.rho == r.rho);
  CHECK(t.S == r.S);
  CHECK(t.b == r.b);
  CHECK(t.c == r.c);
  CHECK(t.e == r.e);
  CHECK(t.M == r.M);
  CHECK(t.alpha0 == r.alpha0);
  CHECK(t.stall_blend == r.stall_blend);
  const auto& a = t.aero;
  const auto& b = r.aero;
  const double ta[] = {a.C_L_0,    a.C_L_alpha,   a.C_L_q,         a.C_L_delta_e,   a.C_D_0,       a.C_D_alpha,   a.C_D_p,
                       a.C_D_q,    a.C_D_delta_e, a.C_m_0,         a.C_m_alpha,     a.C_m_q,       a.C_m_delta_e, a.C_Y_0,
                       a.C_Y_beta, a.C_Y_p,       a.C_Y_r,         a.C_Y_delta_a,   a.C_Y_delta_r, a.C_ell_0,     a.C_ell_beta,
                       a.C_ell_p,  a.C_ell_r,     a.C_ell_delta_a, a.C_ell_delta_r, a.C_n_0,       a.C_n_beta,    a.C_n_p,
                       a.C_n_r,    a.C_n_delta_a, a.C_n_delta_r};
  const double ra[] = {b.C_L_0,    b.C_L_alpha,   b.C_L_q,         b.C_L_delta_e,   b.C_D_0,       b.C_D_alpha,   b.C_D_p,
                       b.C_D_q,    b.C_D_delta_e, b.C_m_0,         b.C_m_alpha,     b.C_m_q,       b.C_m_delta_e, b.C_Y_0,
                       b.C_Y_beta, b.C_Y_p,       b.C_Y_r,         b.C_Y_delta_a,   b.C_Y_delta_r, b.C_ell_0,     b.C_ell_beta,
                       b.C_ell_p,  b.C_ell_r,     b.C_ell_delta_a, b.C_ell_delta_r, b.C_n_0,       b.C_n_beta,    b.C_n_p,
                       b.C_n_r,    b.C_n_delta_a, b.C_n_delta_r};
  for (std::size_t i = 0; i < std::size(ta); ++i) {
    CAPTURE(i);
    CHECK(ta[i] == ra[i]);
  }
  const auto& p = t.prop;
  const auto& q = r.prop;
  CHECK(p.D_prop == q.D_prop);
  CHECK(p.C_T_0 == q.C_T_0);
  CHECK(p.C_T_1 == q.C_T_1);
  CHECK(p.C_T_2 == q.C_T_2);
  CHECK(p.C_Q_0 == q.C_Q_0);
  CHECK(p.C_Q_1 == q.C_Q_1);
  CHECK(p.C_Q_2 == q.C_Q_2);
  CHECK(p.K_Q == q.K_Q);
  CHECK(p.K_V == q.K_V);
  CHECK(p.R_motor == q.R_motor);
  CHECK(p.i0 == q.i0);
  CHECK(p.V_max == q.V_max);
  CHECK(t.servo_tau == r.servo_tau);
  CHECK(t.max_delta_e == doctest::Approx(r.max_delta_e).epsilon(1e-7));
}

TEST_CASE("aircraft: aerosonde.yaml has the book's values; K_Q derives from K_V") {
  const Aircraft a = load_aircraft(kAircraft + "/aerosonde.yaml");
  CHECK(a.mass == 11.0);
  CHECK(a.Jx == 0.8244);
  CHECK(a.alpha0 == 0.47);
  CHECK(a.stall_blend);
  CHECK(a.aero.C_D_p == 0.0);
  CHECK(a.prop.K_Q == doctest::Approx(0.06586).epsilon(1e-3));
  CHECK(a.prop.V_max == doctest::Approx(44.4));
}

TEST_CASE("aircraft: bad files give one line naming the field") {
  const YAML::Node good = YAML::LoadFile(kAircraft + "/anaconda.yaml");
  CHECK(load_error(YAML::Clone(good)) == "(no error)");
  {
    YAML::Node d = YAML::Clone(good);
    d["aero"].remove("C_m_q");
    CHECK(load_error(d) == "test.yaml: aero.C_m_q: missing required field");
  }
  {
    YAML::Node d = YAML::Clone(good);
    d["mass"] = -4.5;
    CHECK(load_error(d) == "test.yaml: mass: value -4.5 must be > 0 kg");
  }
  {
    YAML::Node d = YAML::Clone(good);
    d["inertia"]["Jy"] = -0.3;
    CHECK(load_error(d) == "test.yaml: inertia.Jy: value -0.3 must be > 0 kg m^2");
  }
  {
    YAML::Node d = YAML::Clone(good);
    d["aero"]["C_L_alfa"] = 5.0;
    CHECK(load_error(d) == "test.yaml: aero.C_L_alfa: unknown key");
  }
  {
    YAML::Node d = YAML::Clone(good);
    d["wing"]["S"] = ".nan";
    CHECK(load_error(d) == "test.yaml: wing.S: value .nan is not finite");
  }
  {
    YAML::Node d = YAML::Clone(good);
    d["wing"]["b"] = "wide";
    CHECK(load_error(d) == "test.yaml: wing.b: expected a number, got 'wide'");
  }
  {  // a hard point below the wheels would strike the ground parked (z down: the ground at 0.105 m)
    YAML::Node d = YAML::Clone(good);
    d["gear"]["structure"]["nose"][2] = 0.11;
    CHECK(load_error(d) ==
          "test.yaml: gear.structure.nose: z = 0.11 m is at or below the ground at rest (z = 0.105 m: the wheels less their static "
          "deflection): it would strike the ground parked");
  }
  // ROSflight format: the same rules with ROSflight's names.
  const YAML::Node ros = YAML::LoadFile(kData + "/anaconda_dynamics.yaml");
  CHECK(load_error(YAML::Clone(ros)) == "(no error)");
  {
    YAML::Node d = YAML::Clone(ros);
    d["/fixedwing_forces_and_moments"]["ros__parameters"].remove("C_m_q");
    CHECK(load_error(d) == "test.yaml: C_m_q: missing required field");
  }
  {
    YAML::Node d = YAML::Clone(ros);
    d["/fixedwing_forces_and_moments"]["ros__parameters"]["C_m_qq"] = 1.0;
    CHECK(load_error(d) == "test.yaml: /fixedwing_forces_and_moments.ros__parameters.C_m_qq: unknown key");
  }
  {
    YAML::Node d = YAML::Clone(ros);
    d["/fixedwing_forces_and_moments"]["ros__parameters"]["C_L_beta"] = 0.3;
    CHECK(load_error(d).find("C_L_beta: value 0.3: this coefficient is not part of the uavbook model") != std::string::npos);
  }
  {
    YAML::Node d = YAML::Clone(ros);
    d["/standalone_dynamics"]["ros__parameters"]["Jzz"] = -0.6;
    CHECK(load_error(d) == "test.yaml: /standalone_dynamics.ros__parameters.Jzz: value -0.6 must be > 0 kg m^2");
  }
  CHECK_THROWS_WITH_AS(load_aircraft("/nonexistent/x.yaml"), "/nonexistent/x.yaml: cannot open aircraft file", std::runtime_error);
}

TEST_CASE("aircraft: an implausible value is one line naming file, line, field and value (issue 19)") {
  // finite, but no small aircraft has it: the error names the file, not a diverging trim
  const std::string text = read_text(kAircraft + "/anaconda.yaml");
  const auto cut = [&](const std::string& key, const std::string& value) {
    const std::size_t at = text.find("\n  " + key + ":") + 1;
    const std::size_t eol = text.find('\n', at);
    const std::string edited = text.substr(0, at) + "  " + key + ": " + value + text.substr(eol);
    const std::size_t line = static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) + 1;
    const std::string path = (std::filesystem::temp_directory_path() / "tern_implausible.yaml").string();
    std::ofstream(path) << edited;
    std::string e = "(no error)";
    try {
      load_aircraft(path);
    } catch (const std::runtime_error& x) {
      e = x.what();
    }
    std::filesystem::remove(path);
    return std::make_pair(path + ":" + std::to_string(line) + ": ", e);
  };
  auto [at, e] = cut("C_m_alpha", "2.7e300");
  CHECK(e == at + "aero.C_m_alpha: value 2.7e+300 is outside the plausible range [-100, 100]");
  std::tie(at, e) = cut("Jx", "0");
  CHECK(e == at + "inertia.Jx: value 0 must be > 0 kg m^2");
  std::tie(at, e) = cut("rho", "1225");  // g/m^3 for kg/m^3
  CHECK(e == at + "environment.rho: value 1225 is outside the plausible range [0.01, 2] kg/m^3");
  std::tie(at, e) = cut("C_T_0", "-.inf");
  CHECK(e == at + "propulsion.C_T_0: value -.inf is not finite");
  std::tie(at, e) = cut("C_m_alpha", "-0.5");
  CHECK(e == "(no error)");
}

TEST_CASE("bad input: a NaN state or input is an error, not a NaN flight") {
  Simulator sim(anaconda(), 1);
  StateVector x = sim.state();
  x[V] = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH_AS(sim.set_state(x), "initial state: v is not finite", std::runtime_error);
  Deltas d;
  d.delta_e = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH_AS(sim.set_command(d), "actuators: delta_e is not finite", std::runtime_error);
  d.delta_e = 0;
  d.delta_t = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH_AS(sim.set_command(d), "actuators: delta_t is not finite", std::runtime_error);
  // The simulator kept its valid state and still steps.
  sim.step(0.0025);
  CHECK(all_finite(sim.state()));
}

// ---------------------------------------------------------------- physics invariants ---------

TEST_CASE("physics: free fall without aerodynamics follows p_d = p_d0 + g t^2 / 2") {
  const Aircraft ac = vacuum();
  StateVector x = make_state({0, 0, -1000}, {5, 0, 0}, 0, 0, 0);
  const double dt = 0.0025;
  for (int i = 0; i < 1200; ++i) x = rk4_step(ac, x, Deltas{}, Wind{}, dt);  // 3 s
  const double t = 3.0;
  CHECK(x[PD] == doctest::Approx(-1000 + 0.5 * kGravity * t * t).epsilon(1e-9));
  CHECK(x[PN] == doctest::Approx(15.0).epsilon(1e-9));
  CHECK(x[W] == doctest::Approx(kGravity * t).epsilon(1e-9));
}

TEST_CASE("physics: torque-free rotation conserves angular momentum and kinetic energy") {
  const Aircraft ac = vacuum();
  StateVector x = make_state({0, 0, -1000}, {0, 0, 0}, 0.3, -0.2, 1.0, {1.0, 2.0, 0.5});
  Eigen::Matrix3d J;
  J << ac.Jx, 0, -ac.Jxz, 0, ac.Jy, 0, -ac.Jxz, 0, ac.Jz;
  auto momentum = [&](const StateVector& s) { return Eigen::Vector3d(attitude(s) * (J * Eigen::Vector3d(s.segment<3>(P)))); };
  auto energy = [&](const StateVector& s) {
    const Eigen::Vector3d w = s.segment<3>(P);
    return 0.5 * w.dot(J * w);
  };
  const Eigen::Vector3d H0 = momentum(x);
  const double E0v = energy(x);
  double max_qnorm_err = 0;
  for (int i = 0; i < 4000; ++i) {  // 10 s at 400 Hz
    x = rk4_step(ac, x, Deltas{}, Wind{}, 0.0025);
    max_qnorm_err = std::max(max_qnorm_err, std::fabs(x.segment<4>(E0).norm() - 1.0));
  }
  CHECK((momentum(x) - H0).norm() / H0.norm() < 1e-7);
  CHECK(std::fabs(energy(x) - E0v) / E0v < 1e-7);
  CHECK(max_qnorm_err < 1e-14);
  // The rotation is not trivial: the rates changed (Jxz couples the axes).
  CHECK((x.segment<3>(P) - Eigen::Vector3d(1.0, 2.0, 0.5)).norm() > 0.1);
}

TEST_CASE("model: zero airspeed gives finite forces, and thrust and torque follow the motor model") {
  const Aircraft ac = anaconda();
  const StateVector x = make_state({0, 0, -10}, {0, 0, 0}, 0, 0, 0);
  Deltas d;
  d.delta_t = 1.0;
  ForcesMoments fm;
  const StateVector dx = derivative(ac, x, d, Wind{}, &fm);
  CHECK(dx.allFinite());
  CHECK(fm.air.Va == 0.0);
  CHECK(fm.prop.T_p > 40.0);  // static thrust of the Anaconda's 15 in propeller, ~53 N
  CHECK(fm.prop.T_p < 70.0);
  CHECK(fm.prop.Q_p > 0.0);
  CHECK(fm.m_aero.x() == doctest::Approx(-fm.prop.Q_p));
  // Throttle 0 at rest: the motor does not turn.
  d.delta_t = 0;
  CHECK(propulsion(ac, 0.0, 0.0).Omega == 0.0);
  CHECK(propulsion(ac, 0.0, 0.0).T_p == 0.0);
}

// ---------------------------------------------------------------- trim -----------------------

TEST_CASE("trim: the Anaconda at 17 m/s holds altitude and airspeed open loop for 30 s") {
  const Aircraft ac = anaconda();
  TrimRequest req;
  req.Va = 17.0;
  const TrimResult tr = compute_trim(ac, req);
  CHECK(tr.residual < 1e-8);
  CHECK(tr.delta.delta_t > 0.0);
  CHECK(tr.delta.delta_t < 1.0);
  Simulator sim(ac, 7);
  sim.set_state(tr.x, tr.delta);
  sim.set_command(tr.delta);
  const double h0 = -tr.x[PD];
  double max_dh = 0, max_dva = 0;
  for (int i = 0; i < 12000; ++i) {
    sim.step(0.0025);
    max_dh = std::max(max_dh, std::fabs(-sim.state()[PD] - h0));
    max_dva = std::max(max_dva, std::fabs(air_data(sim.state(), sim.wind()).Va - 17.0));
  }
  CHECK(max_dh < 1.0);
  CHECK(max_dva < 0.3);
  CHECK(sim.state()[PN] == doctest::Approx(17.0 * 30.0).epsilon(0.01));
}

TEST_CASE("trim: a coordinated turn of radius 150 m holds its radius within 5 %") {
  const Aircraft ac = anaconda();
  TrimRequest req;
  req.Va = 17.0;
  req.R = 150.0;
  const TrimResult tr = compute_trim(ac, req);
  CHECK(tr.phi > 0.1);  // right turn, banked right
  Simulator sim(ac, 7);
  sim.set_state(tr.x, tr.delta);
  sim.set_command(tr.delta);
  // Centre of the circle: R to the right of the initial velocity (heading north: east).
  const Eigen::Vector2d centre(0.0, 150.0);
  double max_err = 0;
  const int n = static_cast<int>(2.0 * 3.14159265 * 150.0 / 17.0 / 0.0025);  // one full circle
  for (int i = 0; i < n; ++i) {
    sim.step(0.0025);
    const Eigen::Vector2d p(sim.state()[PN], sim.state()[PE]);
    max_err = std::max(max_err, std::fabs((p - centre).norm() - 150.0) / 150.0);
  }
  CHECK(max_err < 0.05);
}

TEST_CASE("trim: both ROSflight reference files load and trim") {
  const Aircraft an = load_aircraft(kData + "/anaconda_dynamics.yaml");
  const Aircraft ae = load_aircraft(kData + "/aerosonde_dynamics.yaml");
  CHECK(ae.mass == 11.0);
  CHECK(ae.Jx == 0.8224);  // ROSflight's value (the book has 0.8244)
  TrimRequest r1;
  r1.Va = 17.0;
  const TrimResult t1 = compute_trim(an, r1);
  CHECK(t1.residual < 1e-8);
  TrimRequest r2;
  r2.Va = 25.0;
  const TrimResult t2 = compute_trim(ae, r2);
  CHECK(t2.residual < 1e-8);
  CHECK(t2.alpha > 0.0);
  CHECK(t2.alpha < 0.2);
  // Climbing trim too.
  r2.gamma = 0.1;
  CHECK(compute_trim(ae, r2).delta.delta_t > t2.delta.delta_t);
  // Too fast for the motor: a clear error.
  r1.Va = 80.0;
  CHECK_THROWS_AS(compute_trim(an, r1), std::runtime_error);
}

TEST_CASE("model: the polar and linear lift hold below the blending angle, bounded beyond it") {
  const Aircraft an = anaconda();  // no stall blend: linear lift up to kLinearLiftLimit
  CHECK(lift_coefficient(an, 0.1) == doctest::Approx(0.506 + 5.61 * 0.1).epsilon(1e-5));
  const double cl = 0.506 + 5.61 * 0.1;
  CHECK(drag_coefficient(an, 0.1) == doctest::Approx(0.043 + cl * cl / (3.14159265358979 * 0.9 * an.AR())).epsilon(1e-5));
  CHECK(std::fabs(lift_coefficient(an, 3.14159)) < 0.01);
  CHECK(drag_coefficient(an, 3.14159) < 0.05);
  CHECK(drag_coefficient(an, 1.5707) == doctest::Approx(2.043).epsilon(0.01));
  const Aircraft ae = load_aircraft(kAircraft + "/aerosonde.yaml");  // the book's blend, alpha0 0.47
  CHECK(lift_coefficient(ae, 0.2) == doctest::Approx(0.23 + 5.61 * 0.2).epsilon(1e-4));
  CHECK(lift_coefficient(ae, 0.8) < 0.8);  // stalled
}

// ---------------------------------------------------------------- wind -----------------------

TEST_CASE("wind: Dryden turbulence has the MIL-F-8785C intensities; seeded") {
  Dryden d(dryden_preset("moderate"));
  Rng rng(3);
  std::vector<double> u, v, w;
  for (int i = 0; i < 400 * 3600; ++i) {  // one hour at 400 Hz, Va = 17 m/s
    const Eigen::Vector3d g = d.step(0.0025, 17.0, 70.0, 5.0, rng);
    if (i % 40 == 0) {
      u.push_back(g.x());
      v.push_back(g.y());
      w.push_back(g.z());
    }
  }
  CHECK(stddev(u) == doctest::Approx(2.12).epsilon(0.15));
  CHECK(stddev(v) == doctest::Approx(2.12).epsilon(0.15));
  CHECK(stddev(w) == doctest::Approx(1.4).epsilon(0.15));
  CHECK_THROWS_AS(dryden_preset("severe"), std::invalid_argument);
  CosineGust g;
  g.start = 1.0;
  g.duration = 2.0;
  g.amplitude = Eigen::Vector3d(0, 4, 0);
  CHECK(g.at(2.0).y() == doctest::Approx(4.0));
  CHECK(g.at(0.5).norm() == 0.0);
  CHECK(g.at(3.0).norm() == doctest::Approx(0.0));
}

// ---------------------------------------------------------------- sensors --------------------

TEST_CASE("sensors: noise statistics match the parameters") {
  SensorParams p;
  p.accel_bias_walk = p.gyro_bias_walk = p.baro_bias_walk = p.diff_bias_walk = 0.0;
  p.mag_gm_sigma = 0.0;
  p.mag_noise = 3e-6;  // the white part (0 by default, as ROSflight's simulator)
  Sensors s(p, 11);
  Truth t;
  t.x = make_state({0, 0, -100}, {17, 0, 0}, 0, 0, 0);
  t.mass = 4.5;
  t.rho = 1.2682;
  t.fm.f_gravity = Eigen::Vector3d(0, 0, 4.5 * kGravity);
  t.fm.force = Eigen::Vector3d(0, 0, 0);  // level unaccelerated flight: lift balances weight
  t.fm.air.v_air = Eigen::Vector3d(17, 0, 0);
  const int n = 20000;
  std::vector<double> ax, gz, baro, diff, mx, vn;
  for (int i = 0; i < n; ++i) {
    ax.push_back(s.imu(t, 0.0025).accel.z());
    gz.push_back(s.imu(t, 0.0025).gyro.z());
    baro.push_back(s.baro(t, 0.01).pressure);
    diff.push_back(s.diff_pressure(t, 0.01).pressure);
    mx.push_back(s.mag(t, 0.02).field.x());
    vn.push_back(s.gnss(t, 0.1).vel_ned.x());
  }
  const double k = 4.0 / std::sqrt(static_cast<double>(n));  // 4-sigma tolerance of a mean
  CHECK(std::fabs(mean(ax) - (-kGravity + s.accel_bias().z())) < k * p.accel_noise);
  CHECK(stddev(ax) == doctest::Approx(p.accel_noise).epsilon(0.03));
  CHECK(std::fabs(mean(gz) - s.gyro_bias().z()) < k * p.gyro_noise);
  CHECK(stddev(gz) == doctest::Approx(p.gyro_noise).epsilon(0.03));
  CHECK(std::fabs(s.gyro_bias().z()) <= p.gyro_bias_range);
  CHECK(std::fabs(mean(baro) - standard_pressure(p.origin_alt + 100.0)) <= p.baro_bias_range + k * p.baro_noise);
  CHECK(stddev(baro) == doctest::Approx(p.baro_noise).epsilon(0.03));
  CHECK(std::fabs(mean(diff) - 0.5 * 1.2682 * 17 * 17) <= p.diff_bias_range + k * p.diff_noise);
  CHECK(stddev(diff) == doctest::Approx(p.diff_noise).epsilon(0.03));
  const double mx_true = s.earth_field().ned.x();  // level, heading north
  CHECK(std::fabs(mean(mx) - mx_true) < k * p.mag_noise);
  CHECK(stddev(mx) == doctest::Approx(p.mag_noise).epsilon(0.03));
  CHECK(std::fabs(mean(vn) - 17.0) < k * p.gnss_vel_noise);
  CHECK(stddev(vn) == doctest::Approx(p.gnss_vel_noise).epsilon(0.03));
}

TEST_CASE("sensors: the default magnetometer error is ROSflight's Gauss-Markov process") {
  const SensorParams p;  // mag_noise 0, mag_gm_sigma 0.12 uT, mag_gm_tau 1/7 s
  CHECK(p.mag_noise == 0.0);
  Sensors s(p, 12);
  Truth t;
  t.x = make_state({0, 0, -100}, {17, 0, 0}, 0, 0, 0);
  const double mx_true = s.earth_field().ned.x();  // level, heading north
  std::vector<double> e;
  for (int i = 0; i < 50000; ++i) e.push_back(s.mag(t, 0.02).field.x() - mx_true);
  // steady-state sigma, and the sample-to-sample correlation exp(-T_s / tau) = exp(-0.14)
  CHECK(stddev(e) == doctest::Approx(p.mag_gm_sigma).epsilon(0.1));
  double c = 0, v = 0;
  const double m = mean(e);
  for (std::size_t i = 1; i < e.size(); ++i) {
    c += (e[i] - m) * (e[i - 1] - m);
    v += (e[i] - m) * (e[i] - m);
  }
  CHECK(c / v == doctest::Approx(std::exp(-0.02 / p.mag_gm_tau)).epsilon(0.02));
}

TEST_CASE("sensors: GNSS reports lat/lon/alt about the origin; same seed, same draws") {
  SensorParams p;
  p.gnss_h_sigma = p.gnss_v_sigma = 0.0;
  Sensors s(p, 5);
  Truth t;
  t.x = make_state({1000, -500, -120}, {17, 0, 0}, 0, 0, 0);
  const GnssSample g = s.gnss(t, 0.1);
  CHECK(g.fix);
  CHECK(std::fabs(g.alt - (1387.0 + 120.0 + 0.1)) < 0.01);  // + Earth's curvature over 1.1 km
  CHECK(g.lat > 40.2463724);                                // north
  CHECK(g.lon < -111.6474138);                              // west
  const Eigen::Vector3d back = s.origin().to_ned(g.lat, g.lon, g.alt);
  CHECK((back - Eigen::Vector3d(1000, -500, -120)).norm() < 1e-6);
  Sensors a(SensorParams{}, 9), b(SensorParams{}, 9), c(SensorParams{}, 10);
  t.fm.air.v_air = Eigen::Vector3d(17, 0, 0);
  const ImuSample ia = a.imu(t, 0.0025), ib = b.imu(t, 0.0025), ic = c.imu(t, 0.0025);
  CHECK(ia.accel == ib.accel);
  CHECK(ia.gyro == ib.gyro);
  CHECK(ia.accel != ic.accel);
}

TEST_CASE("determinism: the same seed gives bit-identical flights in turbulence") {
  auto fly = [](std::uint64_t seed) {
    Simulator sim(anaconda(), seed);
    TrimRequest req;
    const TrimResult tr = compute_trim(sim.aircraft(), req);
    sim.set_state(tr.x, tr.delta);
    sim.set_command(tr.delta);
    sim.set_turbulence(dryden_preset("moderate"));
    sim.gusts().set_random(0.5, 3.0, 1.0, 3.0);
    for (int i = 0; i < 2000; ++i) sim.step(0.0025);
    return sim.state();
  };
  const StateVector a = fly(42), b = fly(42), c = fly(43);
  CHECK(a == b);
  CHECK(a != c);
}

TEST_CASE("actuators: servo rate limit, deadband and motor lag (the realistic profile's set)") {
  Simulator sim(anaconda(), 1);
  TrimRequest req;
  const TrimResult tr = compute_trim(sim.aircraft(), req);
  sim.set_state(tr.x, tr.delta);
  ActuatorParams a;
  a.servo_rate_limit = 2.0;  // rad/s
  a.servo_deadband = 0.01;   // rad
  a.motor_tau = 0.1;         // s
  sim.set_actuators(a);
  Deltas cmd = tr.delta;
  // a command step inside the deadband does not move the servo
  cmd.delta_a = tr.delta.delta_a + 0.004;
  sim.set_command(cmd);
  for (int i = 0; i < 40; ++i) sim.step(0.0025);
  CHECK(sim.surfaces().delta_a == tr.delta.delta_a);
  // a large step moves at the rate limit: 2 rad/s for 0.1 s = 0.2 rad (the servo lag alone would be faster)
  cmd.delta_a = tr.delta.delta_a + 0.5;
  sim.set_command(cmd);
  for (int i = 0; i < 40; ++i) sim.step(0.0025);
  CHECK(sim.surfaces().delta_a - tr.delta.delta_a == doctest::Approx(0.2).epsilon(1e-9));
  // the motor follows a throttle step with its first-order lag: 1 - exp(-1) after one time constant
  const double t0 = sim.surfaces().delta_t;
  cmd.delta_t = 1.0;
  sim.set_command(cmd);
  for (int i = 0; i < 40; ++i) sim.step(0.0025);
  CHECK((sim.surfaces().delta_t - t0) / (1.0 - t0) == doctest::Approx(1.0 - std::exp(-1.0)).epsilon(1e-9));
  // ideal actuators (the default): the throttle acts at once
  CHECK(actuator_profile("rosflight").motor_tau == 0.0);
  CHECK(actuator_profile("realistic").servo_rate_limit > 0.0);
  CHECK_THROWS_AS(actuator_profile("perfect"), std::invalid_argument);
}
