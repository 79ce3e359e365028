// The equation-error identification (sysid/identify.hpp) on flights the uavbook model flies itself:
// the Aerosonde trimmed at three airspeeds, its surfaces driven by orthogonal multisines, no wind and
// exact measurements. From a prior scaled by 0.6 and 1.5 the coefficients must come back, with the
// truth inside the reported bounds; an unexcited axis must keep the prior and say why.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "sysid/equation_error.hpp"
#include "sysid/identify.hpp"
#include "sysid/identify_moments.hpp"
#include "sysid/identify_drag.hpp"
#include "sysid/motor_lag.hpp"
#include "sysid/regression.hpp"
#include "sysid/sysid_output.hpp"
#include "sysid/verdicts.hpp"
#include "tern/math.hpp"
#include "tern/aero/model.hpp"
#include "tern/aero/trim.hpp"

namespace {

using tern::core::sysid::FlightSeries;

/// The multisine added to the surfaces at time t (rad): disjoint harmonic sets of 0.15 Hz per surface
/// (Schroeder-like phases), `amplitude` split over four lines each, half of it on the aileron.
tern::sim::Deltas multisine(double t, double amplitude) {
  tern::sim::Deltas d{};
  for (int k = 1; k <= 12; ++k) {
    const double f = k * 0.15, ph = tern::kPi * k * k / 12.0;
    const double w = amplitude * std::sin(2.0 * tern::kPi * f * t + ph) / 4.0;
    if (k % 3 == 0)
      d.delta_e += w;
    else if (k % 3 == 1)
      d.delta_a += 0.5 * w;
    else
      d.delta_r += w;
  }
  return d;
}

/// One sample of the series at time t from the model's state x, its derivative dx, forces fm and
/// deflections d, with the flow angles given (the air's, or the flight path's); `last` ends the stretch.
void record(FlightSeries& s, double t, const tern::sim::StateVector& x, const tern::sim::StateVector& dx,
            const tern::sim::ForcesMoments& fm, const tern::sim::Deltas& d, double mass, double alpha, double beta, bool last) {
  namespace sim = tern::sim;
  const Eigen::Vector3d f = fm.specific_force(mass);
  const Eigen::Vector3d euler = tern::euler_from_quaternion(sim::attitude(x));
  s.t.push_back(t);
  s.a_x.push_back(f.x()), s.a_y.push_back(f.y()), s.a_z.push_back(f.z());
  s.p.push_back(x[sim::P]), s.q.push_back(x[sim::Q]), s.r.push_back(x[sim::R]);
  s.p_dot.push_back(dx[sim::P]), s.q_dot.push_back(dx[sim::Q]), s.r_dot.push_back(dx[sim::R]);
  s.delta_a.push_back(d.delta_a), s.delta_e.push_back(d.delta_e), s.delta_r.push_back(d.delta_r), s.delta_t.push_back(d.delta_t);
  s.Va.push_back(fm.air.Va), s.alpha.push_back(alpha), s.beta.push_back(beta), s.qbar.push_back(std::nan(""));
  s.phi.push_back(euler.x()), s.theta.push_back(euler.y()), s.psi.push_back(euler.z());
  s.p_n.push_back(x[sim::PN]), s.p_e.push_back(x[sim::PE]), s.p_d.push_back(std::min(x[sim::PD], -50.0));
  s.u.push_back(x[sim::U]), s.v.push_back(x[sim::V]), s.w.push_back(x[sim::W]);
  s.w_n.push_back(0.0), s.w_e.push_back(0.0), s.w_d.push_back(0.0);
  s.valid.push_back(last ? 0 : 1);
}

/// Appends `seconds` of flight from the trim at Va, the surfaces trim + multisine (rad); with
/// `vertical_gust` (m/s) a vertical gust of that many m/s per line over 12 lines between the
/// multisine's, which the flow angles see.
void fly(const tern::Aircraft& ac, double Va, double seconds, double amplitude, FlightSeries& s, double vertical_gust = 0.0) {
  namespace sim = tern::sim;
  const sim::TrimResult trim = sim::compute_trim(ac, {Va});
  sim::StateVector x = trim.x;
  const double dt = 1.0 / 200.0, t0 = s.t.empty() ? 0.0 : s.t.back() + 1.0;
  for (double t = 0.0; t < seconds; t += dt) {
    const sim::Deltas m = multisine(t, amplitude);
    sim::Deltas d = trim.delta;
    d.delta_a += m.delta_a, d.delta_e += m.delta_e, d.delta_r += m.delta_r;
    sim::Wind wind;
    for (int k = 1; k <= 12 && vertical_gust != 0.0; ++k)
      wind.gust_body.z() += vertical_gust * std::sin(2.0 * tern::kPi * (k * 0.15 + 0.05) * t + 0.7 * k);
    sim::ForcesMoments fm;
    const sim::StateVector dx = sim::derivative(ac, x, d, wind, &fm);
    record(s, t0 + t, x, dx, fm, d, ac.mass, fm.air.alpha, fm.air.beta, !(t + dt < seconds));
    x = sim::rk4_step(ac, x, d, wind, dt);
  }
}

/// Appends `seconds` of closed-loop flight from the trim at Va in a lateral gust the flow angles do
/// not see: a yaw damper and a wings-level roll loop add their answer to the multisine on the
/// aileron and rudder (what a flight with the signal generator logs: commands, and the excitation's
/// part of them when `excitation`); beta is the flight path's (ground velocity in body axes).
void fly_closed_loop(const tern::Aircraft& ac, double Va, double seconds, bool excitation, FlightSeries& s) {
  namespace sim = tern::sim;
  const sim::TrimResult trim = sim::compute_trim(ac, {Va});
  sim::StateVector x = trim.x;
  const double dt = 1.0 / 200.0, t0 = s.t.empty() ? 0.0 : s.t.back() + 1.0;
  for (double t = 0.0; t < seconds; t += dt) {
    const sim::Deltas m = multisine(t, 0.06);
    double gust = 0.0;
    for (int k = 1; k <= 12; ++k) gust += 0.4 * std::sin(2.0 * tern::kPi * (k * 0.15 + 0.05) * t + 1.3 * k);  // m/s, between the lines
    const double phi = tern::euler_from_quaternion(sim::attitude(x)).x();
    sim::Deltas d = trim.delta;
    d.delta_e += m.delta_e;
    d.delta_a += m.delta_a - 0.2 * x[sim::P] - 0.5 * phi;
    d.delta_r += m.delta_r + 0.5 * x[sim::R];  // C_n_delta_r < 0: a positive rudder yaws left
    sim::Wind wind;
    wind.gust_body = Eigen::Vector3d(0.0, gust, 0.0);
    sim::ForcesMoments fm;
    const sim::StateVector dx = sim::derivative(ac, x, d, wind, &fm);
    const Eigen::Vector3d v(x[sim::U], x[sim::V], x[sim::W]);
    record(s, t0 + t, x, dx, fm, d, ac.mass, std::atan2(v.z(), v.x()), std::asin(v.y() / v.norm()), !(t + dt < seconds));
    if (excitation)
      s.exc_delta_a.push_back(m.delta_a), s.exc_delta_e.push_back(m.delta_e), s.exc_delta_r.push_back(m.delta_r),
          s.exc_delta_t.push_back(0.0);
    x = sim::rk4_step(ac, x, d, wind, dt);
  }
}

/// Appends `seconds` of flight from the trim at Va with the surfaces' multisine and a throttle of
/// trim + 0.04 sin at 0.3, 0.7 and 1.3 Hz, the thrust answering the throttle through a first-order
/// lag of `motor_tau` s; the series logs the commanded throttle.
void fly_throttle(const tern::Aircraft& ac, double Va, double seconds, double motor_tau, FlightSeries& s) {
  namespace sim = tern::sim;
  const sim::TrimResult trim = sim::compute_trim(ac, {Va});
  sim::StateVector x = trim.x;
  const double dt = 1.0 / 200.0, t0 = s.t.empty() ? 0.0 : s.t.back() + 1.0;
  double thrust_throttle = trim.delta.delta_t;
  for (double t = 0.0; t < seconds; t += dt) {
    const sim::Deltas m = multisine(t, 0.04);
    sim::Deltas command = trim.delta;
    command.delta_a += m.delta_a, command.delta_e += m.delta_e, command.delta_r += m.delta_r;
    for (const double f : {0.3, 0.7, 1.3}) command.delta_t += 0.04 * std::sin(2.0 * tern::kPi * f * t + f);
    sim::Deltas d = command;
    d.delta_t = thrust_throttle;
    sim::ForcesMoments fm;
    const sim::StateVector dx = sim::derivative(ac, x, d, sim::Wind{}, &fm);
    record(s, t0 + t, x, dx, fm, command, ac.mass, fm.air.alpha, fm.air.beta, !(t + dt < seconds));
    x = sim::rk4_step(ac, x, d, sim::Wind{}, dt);
    thrust_throttle +=
        motor_tau > 0.0 ? (1.0 - std::exp(-dt / motor_tau)) * (command.delta_t - thrust_throttle) : command.delta_t - thrust_throttle;
  }
}

tern::Aircraft aerosonde() { return tern::load_aircraft(TERN_AIRCRAFT_DIR "/aerosonde.yaml"); }

/// The truth's coefficients scaled by 0.6 and 1.5 in turn (the bench's wrong prior).
tern::Aircraft wrong_prior(const tern::Aircraft& truth) {
  tern::Aircraft p = truth;
  double* c = &p.aero.C_L_0;
  const std::size_t n = sizeof(tern::AeroCoefficients) / sizeof(double);
  for (std::size_t i = 0; i < n; ++i) c[i] *= i % 2 == 0 ? 0.6 : 1.5;
  return p;
}

double coefficient(const tern::core::sysid::SysidResult& r, const std::string& name, bool* identified = nullptr, double* se = nullptr) {
  for (const auto& c : r.coefficients)
    if (c.name == name) {
      if (identified) *identified = c.identified;
      if (se) *se = c.std_error;
      return c.estimate;
    }
  FAIL("no coefficient ", name);
  return 0.0;
}

}  // namespace

TEST_CASE("exact flights at three airspeeds: every excited coefficient from a prior off by 0.6 and 1.5") {
  const tern::Aircraft truth = aerosonde();
  FlightSeries s;
  for (const double Va : {20.0, 25.0, 30.0}) fly(truth, Va, 40.0, 0.06, s);
  // the series is raw: each command held over its 5-ms step, as the model flew it (the output-error
  // step would otherwise interpolate it, a 2.5-ms lead on a 47-ms roll mode: C_ell_p off by 3 %)
  tern::core::sysid::SysidOptions o;
  o.output_error.hold_commands = true;
  const auto r = tern::core::sysid::identify(s, wrong_prior(truth), o);
  const tern::AeroCoefficients& T = truth.aero;
  const std::pair<const char*, double> targets[] = {{"C_L_0", T.C_L_0},
                                                    {"C_L_alpha", T.C_L_alpha},
                                                    {"C_m_alpha", T.C_m_alpha},
                                                    {"C_m_q", T.C_m_q},
                                                    {"C_m_delta_e", T.C_m_delta_e},
                                                    {"C_ell_p", T.C_ell_p},
                                                    {"C_ell_delta_a", T.C_ell_delta_a},
                                                    {"C_n_r", T.C_n_r},
                                                    {"C_n_delta_r", T.C_n_delta_r},
                                                    {"C_Y_beta", T.C_Y_beta},
                                                    {"C_n_beta", T.C_n_beta},
                                                    {"C_ell_beta", T.C_ell_beta}};
  for (const auto& [name, value] : targets) {
    bool identified = false;
    double se = 0.0;
    const double e = coefficient(r, name, &identified, &se);
    CAPTURE(name);
    CAPTURE(e);
    CHECK(identified);
    CHECK(std::abs(e - value) <= 0.03 * std::abs(value));
  }
  CHECK(std::abs(r.C_D_trim - r.C_D_trim_prior) > 0.0);
}

TEST_CASE("the polar in vertical gusts: the induced drag follows each moment's C_L^2, not the window's mean C_L squared") {
  // 0.3 m/s on each of 12 lines (0.73 m/s RMS) moves alpha within each trim window; the square of
  // the window's mean C_L misses K var(C_L): e came out 0.859 (truth 0.9)
  const tern::Aircraft truth = aerosonde();
  FlightSeries s;
  for (const double Va : {20.0, 25.0, 30.0}) fly(truth, Va, 40.0, 0.06, s, 0.3);
  tern::core::sysid::SysidOptions o;
  o.output_error.enabled = false;
  const auto r = tern::core::sysid::identify(s, truth, o);
  CAPTURE(r.oswald.estimate);
  CAPTURE(r.C_D_trim);
  CHECK(r.oswald.identified);
  CHECK(std::abs(r.oswald.estimate - truth.e) <= 0.02 * truth.e);
}

TEST_CASE("an output error whose simulated rates explain under half the measured variance is not used: the equation error stands") {
  // the pitch rate read through noise four times its own spread (a log whose simulation cannot
  // follow it, as on the estimator's gust-free airspeed without a pitot): the output error of the
  // pitch rate explains little, and its estimates are not averaged with the equation error's
  const tern::Aircraft truth = aerosonde();
  FlightSeries s;
  for (const double Va : {20.0, 25.0, 30.0}) fly(truth, Va, 40.0, 0.06, s);
  double mean = 0.0, var = 0.0;
  for (const double q : s.q) mean += q / static_cast<double>(s.q.size());
  for (const double q : s.q) var += (q - mean) * (q - mean) / static_cast<double>(s.q.size());
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 4.0 * std::sqrt(var));
  for (double& q : s.q) q += noise(rng);
  tern::core::sysid::SysidOptions o;
  o.output_error.hold_commands = true;
  const auto r = tern::core::sysid::identify(s, wrong_prior(truth), o);
  bool noted = false;
  for (const auto& n : r.notes) noted = noted || n.rfind("output error (pitch): its simulated rates explain R^2", 0) == 0;
  CHECK(noted);
  for (const auto& c : r.coefficients)
    if (c.name.rfind("C_m_", 0) == 0 && c.identified) {
      CAPTURE(c.name);
      CHECK(c.method.find("output error") == std::string::npos);
    }
}

TEST_CASE("a prior too draggy to trim level at the fastest airspeed still instruments alpha: on a descending flight path") {
  const tern::Aircraft truth = aerosonde();
  FlightSeries s;
  for (const double Va : {20.0, 25.0, 30.0}) fly(truth, Va, 40.0, 0.06, s);
  tern::Aircraft prior = wrong_prior(truth);
  const auto trims = [&](double Va) {
    try {
      tern::sim::compute_trim(prior, {Va});
      return true;
    } catch (const std::exception&) {
      return false;
    }
  };
  // parasitic drag (the Aerosonde's file has none) until level at 30 m/s needs more than full throttle
  for (prior.aero.C_D_p = 0.02; prior.aero.C_D_p < 1.0 && trims(30.0);) prior.aero.C_D_p *= 1.25;
  REQUIRE_FALSE(trims(30.0));
  REQUIRE(trims(20.0));
  tern::core::sysid::SysidOptions o;
  o.output_error.hold_commands = true;
  const auto r = tern::core::sysid::identify(s, prior, o);
  bool descended = false, refused = false;
  for (const auto& n : r.notes) {
    descended = descended || n.find("alpha's instrument: the linear model does not trim level at") != std::string::npos;
    refused = refused || n.find("alpha not instrumented") != std::string::npos;
  }
  CHECK(descended);
  CHECK_FALSE(refused);
  for (const auto& [name, value] : {std::pair<const char*, double>{"C_m_q", truth.aero.C_m_q},
                                    {"C_m_delta_e", truth.aero.C_m_delta_e},
                                    {"C_L_alpha", truth.aero.C_L_alpha}}) {
    bool identified = false;
    const double e = coefficient(r, name, &identified);
    CAPTURE(name);
    CAPTURE(e);
    CHECK(identified);
    CHECK(std::abs(e - value) <= 0.03 * std::abs(value));
  }
}

TEST_CASE("a damping derivative or lift slope of the sign physics forbids is not adopted, however tight its bound") {
  namespace sysid = tern::core::sysid;
  const tern::Aircraft prior = aerosonde();
  sysid::SysidResult r;
  r.aircraft = prior;
  const auto add = [&](const char* name, double prior_value, double estimate) {
    sysid::CoefficientEstimate c;
    c.name = name, c.prior = prior_value, c.estimate = estimate, c.std_error = 0.01 * std::abs(estimate), c.identified = true;
    c.method = "output error";
    r.coefficients.push_back(c);
  };
  add("C_ell_p", -0.5, 0.3);     // roll "driven" by its own rate
  add("C_L_alpha", 5.6, -0.29);  // lift falling with alpha
  add("C_m_q", -38.0, -30.0);    // right sign: stands
  add("C_m_alpha", -2.7, 0.4);   // statically unstable airframes exist: stands
  sysid::apply_verdicts(r, prior, {});
  for (std::size_t k : {0u, 1u}) {
    CAPTURE(r.coefficients[k].name);
    CHECK_FALSE(r.coefficients[k].identified);
    CHECK(r.coefficients[k].estimate == r.coefficients[k].prior);
    CHECK(r.coefficients[k].note.find("not adopted: its sign") == 0);
  }
  CHECK(r.coefficients[2].identified);
  CHECK(r.coefficients[3].identified);
  // the same rule the lift's band applies to its C_L_q before alpha is reconstructed from the lift
  CHECK(sysid::forbidden_sign("C_L_q", -66.0).find("its sign: -66") == 0);
  CHECK(sysid::forbidden_sign("C_L_q", 7.95).empty());
  CHECK(sysid::forbidden_sign("C_n_r", 0.0).find("its sign") == 0);
  // a negative parasitic drag (the no-pitot bench's seed 3: -0.014 +- 0.0053) is a failed fit
  CHECK(sysid::forbidden_sign("C_D_p", -0.014).find("its sign: -0.014") == 0);
  CHECK(sysid::forbidden_sign("C_D_p", 0.043).empty());
  // the control derivatives' signs are the sensor log's definitions of its commands: a log whose
  // elevator is the other way round (PX4's and ArduPilot's normalised pitch) gave C_m_delta_e +0.856
  CHECK(sysid::forbidden_sign("C_m_delta_e", 0.8555).find("its sign: 0.8555, where delta_e > 0 pitches the nose down") == 0);
  CHECK(sysid::forbidden_sign("C_m_delta_e", -0.99).empty());
  CHECK(sysid::forbidden_sign("C_ell_delta_a", -0.17).find("its sign: -0.17, where delta_a > 0 rolls right") == 0);
  CHECK(sysid::forbidden_sign("C_ell_delta_a", 0.17).empty());
  CHECK(sysid::forbidden_sign("C_n_delta_r", 0.069).find("its sign: 0.069, where delta_r > 0 yaws the nose left") == 0);
  CHECK(sysid::forbidden_sign("C_n_delta_r", -0.069).empty());
}

TEST_CASE(
    "an estimate within two standard errors of 0 is called indistinguishable from 0, and no manoeuvre is advised for an excited axis") {
  namespace sysid = tern::core::sysid;
  const tern::Aircraft prior = aerosonde();
  sysid::SysidResult r;
  r.aircraft = prior;
  const auto add = [&](const char* name, double estimate, double std_error, const char* method) {
    sysid::CoefficientEstimate c;
    c.name = name, c.prior = 0.0, c.estimate = estimate, c.std_error = std_error, c.identified = true, c.method = method;
    r.coefficients.push_back(c);
  };
  add("C_D_p", 6.4e-5, 0.0022, "trim");       // the Aerosonde's C_D_p is 0: a relative bound never holds
  add("C_Y_beta", -0.4, 0.15, "band");        // beyond 2 standard errors of 0, short of a 0.2 relative bound
  add("C_n_delta_a", -0.004, 0.003, "band");  // near 0, on an axis whose fit explains the data
  r.oswald.identified = true, r.oswald.estimate = 0.67, r.oswald.std_error = 0.02;  // the drag polar's slope, identified
  r.aircraft.e = 0.67;
  r.oswald_C_D_p_held = {0.71, 0.025, true, ""};  // the slope through the prior's C_D_p
  sysid::AxisFit yaw;
  yaw.axis = "yaw", yaw.domain = "band", yaw.r_squared_generalized = 0.58;
  r.fits.push_back(yaw);
  sysid::SysidOptions o;
  o.max_relative_error = 0.2;  // at the default 0.5 the relative rule and the bound of 0 coincide
  sysid::apply_verdicts(r, prior, o);
  CHECK(r.coefficients[0].note.find("not adopted: indistinguishable from 0: 6.4e-05 +- 0.0022") == 0);
  CHECK(r.coefficients[1].note.find("not adopted: its standard error 0.15 exceeds 0.2") == 0);
  const auto note = [&](const std::string& start) {
    for (const auto& n : r.notes)
      if (n.rfind(start, 0) == 0) return n;
    return std::string();
  };
  CHECK(note("drag: nothing identified").empty());  // the Oswald factor is the drag's
  // C_D_p back at the prior: e from the slope fitted through it, not the joint fit's
  CHECK(r.oswald.estimate == 0.71);
  CHECK(r.aircraft.e == 0.71);
  CHECK(note("e (Oswald factor): 0.710 +- 0.025 from the polar's slope fitted again with C_D_p at the prior").find("0.670") !=
        std::string::npos);
  // the drag at trim taken again on the polar the verdicts left (the held e, C_D_p at the prior's 0),
  // its bound the windows' at their mean C_Lw^2 carried to the trim's along the slope's
  r.trim_alpha = 0.06, r.trim_delta_e = -0.1;
  r.trim_drag_bound.C_Lw_squared_mean = 0.3, r.trim_drag_bound.C_D_at_mean = {0.0045, 0.0004, true, ""},
  r.trim_drag_bound.K_std_error = 0.002;
  sysid::drag_at_trim(r, prior);
  CHECK(r.C_D_trim == doctest::Approx(tern::sim::drag_coefficient(r.aircraft, 0.06) - 0.1 * prior.aero.C_D_delta_e).epsilon(1e-12));
  const double C_Lw = prior.aero.C_L_0 + prior.aero.C_L_alpha * 0.06;
  CHECK(r.C_D_trim_std_error == doctest::Approx(std::hypot(0.0004, (C_Lw * C_Lw - 0.3) * 0.002)).epsilon(1e-12));
  r.oswald.identified = false;  // neither C_D_p nor e adopted: the prior's polar has no bound from the data
  sysid::drag_at_trim(r, prior);
  CHECK(std::isnan(r.C_D_trim_std_error));
  CHECK(note("yaw: nothing identified").find("though the flight excited it (its fit explains R^2 0.58)") != std::string::npos);
  CHECK(note("side force: nothing identified").find("fly a rudder doublet") != std::string::npos);  // no side-force fit at all
}

TEST_CASE("the trim terms' bounds hold the propeller's torque and the slopes they are extrapolated with") {
  // C_ell_0 is the rolling moment left once the prior propeller's torque is added back: that torque is
  // a kept prior, uncertain by kPriorUncertainty, and so is C_ell_0 by as much of its coefficient.
  // Exact data: before, C_ell_0's bound was the windows' spread alone (1e-6 here).
  const tern::Aircraft truth = aerosonde();
  FlightSeries s;
  for (const double Va : {20.0, 25.0, 30.0}) fly(truth, Va, 40.0, 0.06, s);
  tern::core::sysid::SysidOptions o;
  o.output_error.hold_commands = true;
  const auto r = tern::core::sysid::identify(s, truth, o);
  double torque = 0.0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double V_xz = s.Va[k] * std::cos(s.beta[k]);
    const double qSb = 0.5 * truth.rho * s.Va[k] * s.Va[k] * truth.S * truth.b;
    torque += tern::sim::propulsion(truth, V_xz, s.delta_t[k]).Q_p / qSb / static_cast<double>(s.size());
  }
  REQUIRE(std::abs(torque) > 1e-4);
  double se_ell = 0.0, se_m = 0.0, se_alpha = 0.0;
  coefficient(r, "C_ell_0", nullptr, &se_ell);
  coefficient(r, "C_m_0", nullptr, &se_m);
  coefficient(r, "C_m_alpha", nullptr, &se_alpha);
  CHECK(se_ell >= 0.45 * std::abs(torque));
  // C_m_0 is the pitching moment extrapolated from the trims' alpha and elevator back to 0: at least
  // C_m_alpha's bound times the mean alpha the flight held (before: a fifteenth of it)
  double alpha = 0.0;
  for (const double a : s.alpha) alpha += a / static_cast<double>(s.size());
  CHECK(se_m >= 0.9 * se_alpha * std::abs(alpha));
}

TEST_CASE("a flight without rudder excitation keeps the rudder's prior and says why") {
  const tern::Aircraft truth = aerosonde();
  FlightSeries s;
  for (const double Va : {20.0, 25.0, 30.0}) fly(truth, Va, 40.0, 0.06, s);
  for (std::size_t k = 1; k < s.size(); ++k) s.delta_r[k] = s.delta_r[0];
  const tern::Aircraft prior = wrong_prior(truth);
  const auto r = tern::core::sysid::identify(s, prior, {});
  bool identified = true;
  CHECK(coefficient(r, "C_n_delta_r", &identified) == prior.aero.C_n_delta_r);
  CHECK_FALSE(identified);
  bool said = false;
  for (const auto& n : r.notes) said = said || n.find("C_n_delta_r: not identifiable: rudder never moved") != std::string::npos;
  CHECK(said);
}

TEST_CASE("of several poorly determined terms the one least determined against its prior keeps it first") {
  // the side force of the Anaconda's seed-3 foreign log: beta, delta_a, delta_r as a weak instrument left them
  Eigen::VectorXd estimate(3), se(3);
  estimate << 1.9, -1.39, -0.451;
  se << 2.2, 1.1, 0.51;
  const std::vector<double> prior = {-0.588, 0.045, 0.114};
  using tern::core::sysid::least_determined;
  CHECK(least_determined(estimate, se, prior, {true, true, true}) == 1);   // C_Y_delta_a: 24 of its prior's size
  CHECK(least_determined(estimate, se, prior, {true, false, true}) == 2);  // then C_Y_delta_r: 4.5 against C_Y_beta's 3.7
  CHECK(least_determined(estimate, se, prior, {true, false, false}) == 0);
  CHECK(least_determined(estimate, se, prior, {false, false, false}) == 3);  // none failed
  // a prior of 0 says nothing of the size: the estimate's is taken
  CHECK(least_determined(estimate, se, {-0.588, 0.0, 0.114}, {true, true, true}) == 2);
  CHECK_THROWS_AS(least_determined(estimate, se, {-0.588, 0.045}, {true, true, true}), std::invalid_argument);
}

TEST_CASE("the coloured-residual bound is wider than the white one when the residuals are correlated") {
  const int n = 2000;
  Eigen::MatrixXd X(n, 1);
  Eigen::VectorXd z(n);
  double v = 0.0;
  for (int k = 0; k < n; ++k) {
    X(k, 0) = std::sin(0.01 * k);
    v = 0.98 * v + 0.1 * std::sin(1.7 * k * k);  // a slowly decaying, correlated residual
    z[k] = 2.0 * X(k, 0) + v;
  }
  const auto e = tern::core::sysid::least_squares(X, z, 200);
  CHECK(e.std_error[0] > 2.0 * e.std_error_white[0]);
}

TEST_CASE("instrumental variables: a regressor with its own error is flattened by least squares, not by IV") {
  // z = 2 x_true; the regressor carries an independent error as large as x_true's spread (a gust
  // in the wind triangle's alpha); the instrument measures x_true through another route
  const int n = 4000;
  Eigen::MatrixXd X(n, 2), Z(n, 2);
  Eigen::VectorXd z(n);
  for (int k = 0; k < n; ++k) {
    const double x = std::sin(0.013 * k), gust = std::sin(0.71 * k + 0.3 * std::sin(0.05 * k)), other = std::sin(1.37 * k * k);
    X(k, 0) = 1.0, X(k, 1) = x + gust;
    Z(k, 0) = 1.0, Z(k, 1) = x + 0.2 * other;
    z[k] = 0.5 + 2.0 * x;
  }
  const auto ls = tern::core::sysid::least_squares(X, z, 3);
  const auto iv = tern::core::sysid::least_squares(X, z, 3, &Z);
  CHECK(ls.theta[1] < 1.4);  // attenuated by var(x) / (var(x) + var(gust)) = 1/2
  CHECK(iv.theta[1] == doctest::Approx(2.0).epsilon(0.02));
  CHECK(iv.theta[0] == doctest::Approx(0.5).epsilon(0.02));
  CHECK(std::abs(iv.theta[1] - 2.0) <= 3.0 * iv.std_error[1]);
  const Eigen::MatrixXd bad = Z.leftCols(1);
  CHECK_THROWS_AS(tern::core::sysid::least_squares(X, z, 3, &bad), std::invalid_argument);
}

TEST_CASE("instrumental variables: the generalized R^2 judges the model, not the instrumented regressor's own error") {
  // a gust 1.5 times x_true's spread in the regressor: the residual z - X theta carries it, so the
  // plain R^2 of a model that holds goes negative; Pesaran and Smith's does not. A term the model
  // lacks (y, as large as 2 x and unseen by the instruments) leaves it about var(2 x) / var(z).
  const int n = 4000;
  Eigen::MatrixXd X(n, 2), Z(n, 2);
  Eigen::VectorXd holds(n), lacks(n);
  for (int k = 0; k < n; ++k) {
    const double x = std::sin(0.013 * k), gust = 1.5 * std::sin(0.71 * k + 0.3 * std::sin(0.05 * k)), other = std::sin(1.37 * k * k);
    const double y = 2.0 * std::sin(0.29 * k);
    X(k, 0) = 1.0, X(k, 1) = x + gust;
    Z(k, 0) = 1.0, Z(k, 1) = x + 0.2 * other;
    holds[k] = 0.5 + 2.0 * x;
    lacks[k] = 0.5 + 2.0 * x + y;
  }
  const auto iv = tern::core::sysid::least_squares(X, holds, 3, &Z);
  CHECK(iv.r_squared < 0.0);
  CHECK(iv.r_squared_generalized > 0.95);
  CHECK(tern::core::sysid::least_squares(X, lacks, 3, &Z).r_squared_generalized == doctest::Approx(0.5).epsilon(0.1));  // var(2x) / var(z)
  const auto ls = tern::core::sysid::least_squares(X, holds, 3);
  CHECK(ls.r_squared_generalized == ls.r_squared);  // without instruments: the plain R^2
  // the frequency domain's: the same rows as complex ones
  const Eigen::MatrixXcd Xc = X.cast<std::complex<double>>(), Zc = Z.cast<std::complex<double>>();
  const auto ivf = tern::core::sysid::least_squares_frequency(Xc, holds.cast<std::complex<double>>(), &Zc);
  CHECK(ivf.theta[1] == doctest::Approx(iv.theta[1]).epsilon(1e-9));
  CHECK(ivf.r_squared_generalized > 0.95);
  CHECK(tern::core::sysid::least_squares_frequency(Xc, lacks.cast<std::complex<double>>(), &Zc).r_squared_generalized < 0.6);
}

TEST_CASE("the flow angles of the reconstructed flight path: ground velocity less the steady wind, in body axes") {
  FlightSeries s;
  const double phi = 0.3, theta = 0.1, psi = 2.0, alpha = 0.06, beta = -0.03, Va = 22.0;
  const Eigen::Vector3d wind(3.0, -4.0, 0.0);
  const Eigen::Vector3d v_air(Va * std::cos(alpha) * std::cos(beta), Va * std::sin(beta), Va * std::sin(alpha) * std::cos(beta));
  const Eigen::Matrix3d R = tern::rotation_from_euler(phi, theta, psi);
  const Eigen::Vector3d v_ground = v_air + R.transpose() * wind;
  s.t = {0.0, 0.02};
  for (int k = 0; k < 2; ++k) {
    s.phi.push_back(phi), s.theta.push_back(theta), s.psi.push_back(psi);
    s.u.push_back(v_ground.x()), s.v.push_back(v_ground.y()), s.w.push_back(v_ground.z());
    s.w_n.push_back(wind.x()), s.w_e.push_back(wind.y()), s.w_d.push_back(wind.z());
  }
  s.u[1] = std::nan("");
  tern::core::sysid::flow_angles_from_steady_wind(s);
  CHECK(s.alpha[0] == doctest::Approx(alpha).epsilon(1e-12));
  CHECK(s.beta[0] == doctest::Approx(beta).epsilon(1e-12));
  CHECK(std::isnan(s.alpha[1]));
  CHECK(std::isnan(s.beta[1]));
}

TEST_CASE("an estimate the aircraft format refuses is not adopted: the prior kept, one note, the file loads") {
  namespace sysid = tern::core::sysid;
  const std::string prior = std::string(TERN_AIRCRAFT_DIR) + "/aerosonde.yaml";
  sysid::SysidResult r;
  r.aircraft = tern::load_aircraft(prior);
  sysid::CoefficientEstimate q;
  q.name = "C_m_q", q.prior = r.aircraft.aero.C_m_q, q.estimate = 888.8, q.std_error = 2.0, q.identified = true;
  sysid::CoefficientEstimate a;
  a.name = "C_L_alpha", a.prior = r.aircraft.aero.C_L_alpha, a.estimate = 5.0, a.std_error = 0.1, a.identified = true;
  r.coefficients = {q, a};
  r.aircraft.e = 1.53, r.oswald.estimate = 1.53, r.oswald.identified = true;
  sysid::keep_loadable(r, {"log", prior, "estimate", "options"});
  CHECK_FALSE(r.coefficients[0].identified);
  CHECK(r.coefficients[0].estimate == r.coefficients[0].prior);
  CHECK(r.coefficients[0].note.find("plausible range") != std::string::npos);
  CHECK(r.coefficients[1].identified);
  CHECK(r.aircraft.aero.C_L_alpha == 5.0);
  CHECK(r.aircraft.e == doctest::Approx(0.9));
  CHECK_FALSE(r.oswald.identified);
  CHECK(r.notes.size() == 2);
}

TEST_CASE("a closed-loop flight in a lateral gust: the excitation's part of the commands instruments the side force") {
  // the controller's share of the aileron and rudder answers the gust, which the flight path's beta
  // misses: instruments built from the whole commands carry the gust, those from the excitation do not
  const tern::Aircraft truth = aerosonde();
  double error[2] = {0.0, 0.0};
  for (const bool excitation : {false, true}) {
    FlightSeries s;
    for (const double Va : {20.0, 25.0, 30.0}) fly_closed_loop(truth, Va, 60.0, excitation, s);
    tern::core::sysid::SysidOptions o;
    o.output_error.enabled = false;
    const auto r = tern::core::sysid::identify(s, wrong_prior(truth), o);
    double se = 0.0;
    const double e = coefficient(r, "C_Y_beta", nullptr, &se);
    error[excitation] = std::abs(e / truth.aero.C_Y_beta - 1.0);
    CAPTURE(excitation);
    CAPTURE(e);
    CAPTURE(se);
    if (excitation) CHECK(std::abs(e - truth.aero.C_Y_beta) <= 3.0 * se);
  }
  CHECK(error[1] < 0.05);  // measured 0.013 with the excitation, 0.29 with the whole commands
  CHECK(error[0] > 2.0 * error[1]);
}

TEST_CASE("beta from the side force carries C_Y_beta's scale: the beta derivatives' bounds carry its relative uncertainty") {
  // instruments from the whole commands (no excitation table) leave C_Y_beta off by a third; beta,
  // and with it C_ell_beta and C_n_beta, take that scale
  const tern::Aircraft truth = aerosonde();
  FlightSeries s;
  for (const double Va : {20.0, 25.0, 30.0}) fly_closed_loop(truth, Va, 60.0, false, s);
  tern::core::sysid::SysidOptions o;
  o.output_error.enabled = false;
  const auto r = tern::core::sysid::identify(s, wrong_prior(truth), o);
  bool identified = false;
  double se_Y = 0.0;
  const double C_Y_beta = coefficient(r, "C_Y_beta", &identified, &se_Y);
  REQUIRE(identified);
  for (const auto& [name, value] : {std::pair{"C_ell_beta", truth.aero.C_ell_beta}, std::pair{"C_n_beta", truth.aero.C_n_beta}}) {
    double se = 0.0;
    const double e = coefficient(r, name, &identified, &se);
    const std::string coefficient_name = name;
    CAPTURE(coefficient_name);
    CAPTURE(e);
    CAPTURE(se);
    if (!identified) continue;
    CHECK(se >= se_Y / std::abs(C_Y_beta) * std::abs(e));
    CHECK(std::abs(e - value) <= 3.0 * se);  // before: C_ell_beta -0.091 +- 0.0015 (truth -0.13), C_n_beta 0.052 +- 0.0039 (0.073)
  }
}

TEST_CASE("the lift's alpha carries C_L_alpha's scale: C_m_alpha's bound carries its relative uncertainty") {
  // airspeeds close together: alpha's trim spreads less than 1 deg, C_L_alpha keeps its prior
  // (x1.5), and the alpha reconstructed from the lift is the true one over 1.5; C_m_alpha fitted on
  // it comes out x1.5
  const tern::Aircraft truth = aerosonde();
  FlightSeries s;
  for (const double Va : {24.0, 25.0, 26.0}) fly(truth, Va, 40.0, 0.15, s);
  tern::core::sysid::SysidOptions o;
  o.output_error.hold_commands = true;
  const auto r = tern::core::sysid::identify(s, wrong_prior(truth), o);
  bool identified = true;
  coefficient(r, "C_L_alpha", &identified);
  REQUIRE_FALSE(identified);
  double se = 0.0;
  const double e = coefficient(r, "C_m_alpha", &identified, &se);
  CAPTURE(e);
  CAPTURE(se);
  CHECK(identified);
  CHECK(std::abs(e - truth.aero.C_m_alpha) <= 3.0 * se);  // -4.11 +- 2.06 (before: +- 0.0085)
}

TEST_CASE("a flying wing (no rudder): it trims in sideslip, and the timing fit leaves the still rudder out") {
  tern::Aircraft truth = aerosonde();
  truth.aero.C_Y_delta_r = truth.aero.C_ell_delta_r = truth.aero.C_n_delta_r = 0.0;
  const tern::sim::TrimResult trim = tern::sim::compute_trim(truth, {25.0, 0.0, 150.0});
  CHECK(trim.delta.delta_r == 0.0);
  CHECK(trim.residual < 1e-8);
  CHECK(std::abs(trim.beta) > 1e-4);  // the turn's side force and yawing moment balanced in sideslip
  FlightSeries s;
  // open loop and no rudder to damp the yaw: short stretches, before the spiral mode diverges
  for (const double Va : {20.0, 25.0, 30.0})
    for (int k = 0; k < 3; ++k) fly(truth, Va, 12.0, 0.25, s);
  for (double& d : s.delta_r) d = 0.0;  // a log without a rudder channel
  tern::core::sysid::SysidOptions o;
  o.estimate_delays = true;
  const auto r = tern::core::sysid::identify(s, wrong_prior(truth), o);
  // the rudder's delay and C_n_delta_r out of the timing fit: the aileron's delay keeps a finite bound
  CHECK(r.delay_shift[0].identified);
  CHECK(std::isfinite(r.delay_shift[0].std_error));
  CHECK(std::abs(r.delay_shift[0].estimate) < 0.005);  // within the 200-Hz series' step of the truth's 0
  CHECK_FALSE(r.delay_shift[2].identified);
  CHECK(r.delay_shift[2].note == "the rudder never moved more than 0.3 deg about its trim");
  CHECK(coefficient(r, "C_ell_p") == doctest::Approx(truth.aero.C_ell_p).epsilon(0.1));
  CHECK(coefficient(r, "C_ell_delta_a") == doctest::Approx(truth.aero.C_ell_delta_a).epsilon(0.1));
}

TEST_CASE("the motor's lag from the x force: 0.1 s found within 0.015 s, and at most 0.01 s where the thrust follows at once") {
  // Before: the throttle took the servos' lag (0.02 s); the x force then carried the thrust of the
  // commands, not of the lagged throttle. The logged throttle is the command; `throttle` lags it
  // by each tau on the series' own samples.
  namespace sysid = tern::core::sysid;
  const tern::Aircraft ac = aerosonde();
  for (const double truth : {0.1, 0.0}) {
    FlightSeries s;
    for (const double Va : {20.0, 25.0, 30.0}) fly_throttle(ac, Va, 40.0, truth, s);
    const std::vector<double> command = s.delta_t;
    const auto throttle = [&](double tau) {
      std::vector<double> out(command.size());
      double y = command.front();
      for (std::size_t k = 0; k < command.size(); ++k) {
        const double dt = k == 0 || s.t[k] - s.t[k - 1] > 0.1 ? 0.0 : s.t[k] - s.t[k - 1];
        if (dt == 0.0) y = command[k];  // a new stretch starts at its trim
        y += tau > 0.0 ? (1.0 - std::exp(-dt / tau)) * (command[k] - y) : command[k] - y;
        out[k] = y;
      }
      return out;
    };
    const sysid::MotorLag m = sysid::estimate_motor_lag(s, throttle, ac, sysid::SysidOptions{}.airborne, 0.02);
    CAPTURE(truth);
    CAPTURE(m.line);
    if (truth > 0.0) {
      REQUIRE(m.tau.identified);
      CHECK(std::abs(m.tau.estimate - truth) <= 0.015);  // the grid's 0.01 s, and the flight's throttle a 5-ms step late
      CHECK(m.tau.std_error < 0.02);
    } else {  // adopted, not the servos' 0.02 s kept
      REQUIRE(m.tau.identified);
      CHECK(m.tau.estimate <= 0.01);
    }
  }
  CHECK_THROWS_AS(sysid::estimate_motor_lag(FlightSeries{}, {}, ac, {}, 0.02, {0.0, 0.005}), std::invalid_argument);
}

TEST_CASE("gyros that read a share of each other's rate: the rate derivatives' bounds carry it") {
  // a roll gyro reading p + kappa r and a yaw gyro reading r + kappa p (a datasheet's cross-axis
  // sensitivity): the rolling moment's p regressor then carries kappa r, and C_ell_r comes out
  // C_ell_r - kappa C_ell_p, which no residual shows
  const tern::Aircraft truth = aerosonde();
  FlightSeries s;
  for (const double Va : {20.0, 25.0, 30.0}) fly(truth, Va, 40.0, 0.06, s);
  const double kappa = 0.02;
  for (std::size_t k = 0; k < s.t.size(); ++k) {
    const double p = s.p[k], r = s.r[k], p_dot = s.p_dot[k], r_dot = s.r_dot[k];
    s.p[k] = p + kappa * r, s.r[k] = r + kappa * p;
    s.p_dot[k] = p_dot + kappa * r_dot, s.r_dot[k] = r_dot + kappa * p_dot;
  }
  tern::core::sysid::SysidOptions o;
  o.output_error.hold_commands = true;
  for (const double stated : {0.0, kappa}) {
    o.gyro_cross_axis = stated;
    const auto r = tern::core::sysid::identify(s, wrong_prior(truth), o);
    bool identified = false;
    double se = 0.0;
    const double e = coefficient(r, "C_ell_r", &identified, &se);
    CAPTURE(stated);
    CAPTURE(e);
    CAPTURE(se);
    REQUIRE(identified);
    CHECK(std::abs(e - truth.aero.C_ell_r) > 0.5 * kappa * std::abs(truth.aero.C_ell_p));  // the coupling's bias is there
    if (stated > 0.0)
      CHECK(std::abs(e - truth.aero.C_ell_r) <= 3.0 * se);
    else
      CHECK(std::abs(e - truth.aero.C_ell_r) > 3.0 * se);  // a bound without it does not hold the truth
  }
}

TEST_CASE("the output error retries a dominant derivative the band left poorly determined, judged against its prior's size") {
  using tern::core::sysid::CoefficientEstimate;
  // calm air, bench/book_sim.py: the yaw band's pieces disagreed on C_n_r, the prior 40 % off
  CoefficientEstimate n_r{"C_n_r", -0.057, -0.057, 0.0, false, "band", "poorly determined: -0.0764 +- 0.042"};
  CHECK(tern::core::sysid::retried_by_output_error(n_r));
  CHECK(tern::core::sysid::retry_determined(0.5, n_r, -0.0947, 0.0022));
  // a cross derivative stays where the band left it; so do a term it found collinear or not excited
  CHECK_FALSE(tern::core::sysid::retried_by_output_error(
      {"C_ell_delta_r", 0.00144, 0.00144, 0.0, false, "band", "poorly determined: 0.0035 +- 0.0048"}));
  CHECK_FALSE(tern::core::sysid::retried_by_output_error({"C_n_r", -0.057, -0.057, 0.0, false, "band", "collinear with C_n_p (r = 0.97)"}));
  CHECK_FALSE(tern::core::sysid::retried_by_output_error({"C_n_r", -0.057, -0.057, 0.0, false, "band", "yaw rate never above 5 deg/s"}));
  CHECK_FALSE(tern::core::sysid::retried_by_output_error({"C_n_r", -0.057, -0.09, 0.01, true, "band", ""}));
  // bounded within half of itself but not of the size the prior expects: thrown far from any value
  const CoefficientEstimate small{"C_ell_delta_r", 0.0014, 0.0014, 0.0, false, "band", "poorly determined: 0.0035 +- 0.0048"};
  CHECK_FALSE(tern::core::sysid::retry_determined(0.5, small, -0.012, 0.004));
  CHECK(tern::core::sysid::retry_determined(0.5, small, 0.0016, 0.0005));
  // a prior of 0 says nothing of the size: the estimate's is taken
  CHECK(tern::core::sysid::retry_determined(0.5, {"C_n_beta", 0.0, 0.0, 0.0, false, "band", ""}, 0.07, 0.01));
  CHECK_FALSE(tern::core::sysid::retry_determined(0.5, {"C_n_beta", 0.0, 0.0, 0.0, false, "band", ""}, 0.07, 0.04));
}
