// core/apps/sysid/tests/test_validate.cpp: `tern validate`'s method (sysid/validate.hpp) on a flight
// made by the model itself: the Aerosonde trimmed at 25 m/s in a steady wind, doublets on every
// surface and a throttle step, integrated exactly as validate integrates (inputs held between
// samples, RK4), no noise. The true file must score ~0 everywhere; the file with its aerodynamic
// coefficients scaled by 0.6 clearly worse; bad logs fail in one line.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include <yaml-cpp/yaml.h>

#include "config/error.hpp"
#include "sysid/logged_state.hpp"
#include "sysid/validate.hpp"
#include "tern/aero/trim.hpp"

using namespace tern;
using namespace tern::core::sysid;

namespace {

const std::string kAerosonde = std::string(TERN_SOURCE_DIR) + "/configs/aircraft/aerosonde.yaml";
constexpr double kDt = 0.02;  ///< s, the series' sample interval (50 Hz, flight_data's default rate)

/// The Aerosonde file with every aerodynamic coefficient times `factor`.
Aircraft scaled_aerosonde(double factor) {
  YAML::Node doc = YAML::LoadFile(kAerosonde);
  for (auto entry : doc["aero"]) entry.second = entry.second.as<double>() * factor;
  return parse_aircraft(doc, "aerosonde x" + std::to_string(factor));
}

/// Trim inputs plus a doublet on each surface (elevator at 2 s, aileron at 8 s, rudder at 14 s)
/// and a throttle step from 20 to 25 s.
sim::Deltas inputs_at(const sim::Deltas& trim, double t) {
  auto doublet = [t](double start) { return t >= start && t < start + 1 ? 0.05 : t >= start + 1 && t < start + 2 ? -0.05 : 0.0; };
  sim::Deltas d = trim;
  d.delta_e += doublet(2), d.delta_a += doublet(8), d.delta_r += doublet(14);
  d.delta_t += t >= 20 && t < 25 ? 0.1 : 0.0;
  return d;
}

void record(FlightSeries& s, const Aircraft& ac, const sim::StateVector& x, const sim::Deltas& d, const sim::Wind& wind, double t) {
  sim::ForcesMoments fm;
  const sim::StateVector x_dot = sim::derivative(ac, x, d, wind, &fm);
  const Eigen::Vector3d f = fm.specific_force(ac.mass), euler = euler_from_quaternion(sim::attitude(x));
  s.t.push_back(t);
  s.a_x.push_back(f.x()), s.a_y.push_back(f.y()), s.a_z.push_back(f.z());
  s.p.push_back(x[sim::P]), s.q.push_back(x[sim::Q]), s.r.push_back(x[sim::R]);
  s.p_dot.push_back(x_dot[sim::P]), s.q_dot.push_back(x_dot[sim::Q]), s.r_dot.push_back(x_dot[sim::R]);
  s.delta_a.push_back(d.delta_a), s.delta_e.push_back(d.delta_e), s.delta_r.push_back(d.delta_r), s.delta_t.push_back(d.delta_t);
  s.Va.push_back(fm.air.Va), s.alpha.push_back(fm.air.alpha), s.beta.push_back(fm.air.beta);
  s.phi.push_back(euler.x()), s.theta.push_back(euler.y()), s.psi.push_back(euler.z());
  s.p_n.push_back(x[sim::PN]), s.p_e.push_back(x[sim::PE]), s.p_d.push_back(x[sim::PD]);
  s.u.push_back(x[sim::U]), s.v.push_back(x[sim::V]), s.w.push_back(x[sim::W]);
  s.w_n.push_back(wind.steady_ned.x()), s.w_e.push_back(wind.steady_ned.y()), s.w_d.push_back(wind.steady_ned.z());
  s.valid.push_back(1);
}

/// `seconds` of the true aircraft's flight at 50 Hz in 4 m/s of wind from the south-west.
FlightSeries synthetic_flight(const Aircraft& ac, double seconds) {
  sim::TrimRequest req;
  req.Va = 25.0, req.altitude = 200.0;
  const sim::TrimResult trim = sim::compute_trim(ac, req);
  sim::Wind wind;
  wind.steady_ned = {2.8, 2.8, 0.0};
  sim::StateVector x = trim.x;  // the trim's air-relative velocity plus the wind, in body axes
  x.segment<3>(sim::U) += sim::attitude(x).toRotationMatrix().transpose() * wind.steady_ned;
  FlightSeries s;
  for (int k = 0; k * kDt < seconds; ++k) {
    const sim::Deltas d = inputs_at(trim.delta, k * kDt);
    record(s, ac, x, d, wind, k * kDt);
    for (int i = 0; i < 4; ++i) x = sim::rk4_step(ac, x, d, wind, kDt / 4);
  }
  return s;
}

}  // namespace

TEST_CASE("the true aircraft scores ~0 on its own flight; coefficients x0.6 score clearly worse") {
  const Aircraft truth = load_aircraft(kAerosonde);
  const FlightSeries s = synthetic_flight(truth, 30.0);
  const ValidateOptions o;
  const std::vector<Window> windows = airborne_windows(s, o, "synthetic");
  REQUIRE(windows.size() == 5);  // 0-5, ..., 20-25 s; 25-30 s lacks the sample at 30 s that closes it
  for (const Window& w : windows) CHECK(w.end - w.begin == 250);
  const AircraftScore good = score_aircraft(s, truth, "aerosonde.yaml", windows, o);
  const AircraftScore bad = score_aircraft(s, scaled_aerosonde(0.6), "scaled.yaml", windows, o);
  for (std::size_t c = 0; c < kChannels; ++c) {
    INFO(std::string(kChannelSpecs[c].name), ": true NRMSE ", good.fit[c].nrmse, " U ", good.fit[c].theil_u, "; x0.6 NRMSE ",
         bad.fit[c].nrmse, " U ", bad.fit[c].theil_u);
    CHECK(good.fit[c].samples == 5 * 249);
    CHECK(good.fit[c].nrmse < 1e-6);
    CHECK(good.fit[c].theil_u < 1e-6);
    CHECK(bad.fit[c].theil_u > good.fit[c].theil_u);
  }
  for (const char* name : {"p", "q", "r", "alpha", "theta"}) {
    std::size_t c = 0;
    while (std::string(kChannelSpecs[c].name) != name) ++c;
    INFO(name, ": x0.6 NRMSE ", bad.fit[c].nrmse);
    CHECK(bad.fit[c].nrmse > 0.3);
  }
  for (std::size_t a = 0; a < kAxes; ++a) {
    INFO(std::string(kAxisSpecs[a].name), ": true ", good.one_step[a].rms, " x0.6 ", bad.one_step[a].rms, " (",
         bad.one_step[a].coefficient_rms, ")");
    CHECK(good.one_step[a].rms < 1e-9);
    CHECK(bad.one_step[a].rms > 100 * good.one_step[a].rms + 1e-3);
  }
  CHECK(good.prediction.diverged == 0);
}

TEST_CASE("overall_scores: the geometric mean over the channels every file has, the files ranked best first") {
  auto file = [](std::array<double, kChannels> nrmse) {
    AircraftScore f;
    for (std::size_t c = 0; c < kChannels; ++c) f.fit[c].nrmse = nrmse[c];
    return f;
  };
  const double nan = std::nan("");
  // [1] better than [2] on every channel but p, where the turbulence leaves both near 1; [3] misses beta (NaN)
  const AircraftScore a = file({0.25, 0.6, 0.85, 0.12, 0.8, 0.9, 0.08, 0.35});
  const AircraftScore b = file({0.24, 0.87, 0.87, 0.7, 0.83, 0.92, 0.27, 2.5});
  const AircraftScore c = file({0.5, 0.5, 0.5, 0.5, 0.5, nan, 0.5, 0.5});
  const OverallScores o = overall_scores({b, a, c});
  CHECK(o.channels == std::vector<std::string>{"p", "q", "r", "Va", "alpha", "phi", "theta"});  // beta: not every file has it
  double log_a = 0.0;
  for (const std::size_t ch : {0, 1, 2, 3, 4, 6, 7}) log_a += std::log(a.fit[ch].nrmse);
  CHECK(o.nrmse[1] == doctest::Approx(std::exp(log_a / 7.0)).epsilon(1e-12));
  CHECK(o.nrmse[2] == doctest::Approx(0.5));
  CHECK(o.ranking == std::vector<std::size_t>{1, 2, 0});  // a (0.29), c (0.5), b (0.6)
  // a file x % better on every channel scores x % better; ties keep the files' order
  AircraftScore half = a;
  for (auto& f : half.fit) f.nrmse *= 0.5;
  const OverallScores h = overall_scores({a, half, a});
  CHECK(h.nrmse[1] == doctest::Approx(0.5 * h.nrmse[0]).epsilon(1e-12));
  CHECK(h.ranking == std::vector<std::size_t>{1, 0, 2});
  // no channel every file has: NaN scores, the files' own order
  const OverallScores none = overall_scores({file({nan, nan, nan, nan, nan, nan, nan, nan}), a});
  CHECK(none.channels.empty());
  CHECK(std::isnan(none.nrmse[0]));
  CHECK(none.ranking == std::vector<std::size_t>{0, 1});
}

TEST_CASE("channel_fit: NRMSE and Theil's U of a known error; angles compared across +-pi") {
  std::vector<double> y, yhat;
  for (int k = 0; k < 101; ++k) y.push_back(std::sin(0.1 * k)), yhat.push_back(std::sin(0.1 * k) + 0.1);
  const std::vector<Window> all = {{0, 101}};
  const ChannelFit f = channel_fit(y, yhat, all, false);
  double mean = 0, var = 0, ms = 0, ms_hat = 0;
  for (int k = 1; k < 101; ++k) mean += y[k] / 100, ms += y[k] * y[k] / 100, ms_hat += yhat[k] * yhat[k] / 100;
  for (int k = 1; k < 101; ++k) var += (y[k] - mean) * (y[k] - mean) / 100;
  CHECK(f.samples == 100);  // the window's first sample is the log itself: not scored
  CHECK(f.rms_error == doctest::Approx(0.1));
  CHECK(f.nrmse == doctest::Approx(0.1 / std::sqrt(var)));
  CHECK(f.theil_u == doctest::Approx(0.1 / (std::sqrt(ms) + std::sqrt(ms_hat))));
  const std::vector<double> near_pi(101, 3.1), across(101, 3.1 - 2 * kPi + 0.01);
  CHECK(channel_fit(near_pi, across, all, true).rms_error == doctest::Approx(0.01));
}

TEST_CASE("bad logs: an estimate never valid, or no whole window airborne, is one line naming the log") {
  FlightSeries s = synthetic_flight(load_aircraft(kAerosonde), 12.0);
  const ValidateOptions o;
  FlightSeries never = s;
  std::fill(never.valid.begin(), never.valid.end(), 0);
  CHECK_THROWS_WITH_AS(airborne_windows(never, o, "LOG"), doctest::Contains("LOG: the estimate never became valid"),
                       tern::core::ConfigError);
  for (std::size_t k = 0; k < s.size(); ++k)  // standing on the ground (height 0) but for 2 s at 4-6 s and 3 s at 8-11 s
    if (!((s.t[k] >= 4 && s.t[k] < 6) || (s.t[k] >= 8 && s.t[k] < 11))) s.p_d[k] = 0.0, s.u[k] = s.v[k] = s.w[k] = 0.0;
  CHECK_THROWS_WITH_AS(airborne_windows(s, o, "LOG"), doctest::Contains("LOG: no 5-s window airborne"), tern::core::ConfigError);
  ValidateOptions two = o;
  two.window_s = 2.0;
  CHECK(airborne_windows(s, two, "LOG").size() == 1);  // 8-10 s; 4-6 s and 10-11 s lack an airborne sample that closes them
}
