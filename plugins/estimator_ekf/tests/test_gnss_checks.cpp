// The GNSS start-up checks (gnss_checks.hpp) alone, and in the estimator: the origin and the
// barometer's datum from a settled receiver, not from its first fixes.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>

#include "fly.hpp"
#include "tern/geodesy.hpp"
#include "tern/estimator_ekf/estimator.hpp"
#include "tern/estimator_ekf/gnss_checks.hpp"
#include "truth_sim.hpp"

using namespace tern;
using namespace tern::ekf;
using namespace tern::ekf::test;

namespace {

using Motion = GnssChecks::Motion;

/// A fix at t seconds, at rest at Zurich's field, with the accuracies and satellites given.
msg::Gnss fix_at(double t, double h_acc = 1.0, double v_acc = 1.5, double s_acc = 0.2, int sats = 12) {
  msg::Gnss g;
  g.stamp = from_seconds(t);
  g.fix_type = msg::FixType::fix_3d;
  g.num_sats = static_cast<std::uint8_t>(sats);
  g.lat = 47.389156;
  g.lon = 8.033634;
  g.alt = 366.7;
  g.h_acc = h_acc;
  g.v_acc = v_acc;
  g.s_acc = s_acc;
  return g;
}

/// Feeds 10-Hz fixes from t0 to t1 (s), each made by make(t); returns the first time it passed (or -1).
template <class Make>
double feed(GnssChecks& c, double t0, double t1, Motion motion, Make make) {
  for (int k = 0; t0 + 0.1 * k <= t1 + 1e-9; ++k) {
    const double t = t0 + 0.1 * k;
    const bool was = c.passed();
    if (c.update(make(t), true, motion) && !was) return t;
  }
  return c.passed() ? t0 : -1.0;
}

/// Passed at `expected` s, give or take one 10-Hz fix (the stamps' rounding to ns).
bool passed_near(double t, double expected) { return std::fabs(t - expected) <= 0.101; }

}  // namespace

TEST_CASE("GNSS checks: a receiver good from its first fix passes after the hold time (EKF2_REQ_GPS_H), not before") {
  GnssChecks c;
  CHECK(feed(c, 0.0, 9.9, Motion::at_rest, [](double t) { return fix_at(t); }) < 0.0);
  CHECK(c.failing() == 0);
  CHECK(passed_near(feed(c, 10.0, 12.0, Motion::at_rest, [](double t) { return fix_at(t); }), 10.0));
  CHECK(c.passed_stamp() == from_seconds(10.0));
  CHECK(c.first_stamp() == 0);
}

TEST_CASE("GNSS checks: each reported quantity over its PX4 limit fails; 0 (not reported) passes; the hold restarts") {
  struct Case {
    msg::Gnss g;
    std::uint32_t bit;
  };
  for (const Case& k : {Case{fix_at(0, 3.5), gnss_check::eph}, Case{fix_at(0, 1.0, 5.5), gnss_check::epv},
                        Case{fix_at(0, 1.0, 1.5, 0.6), gnss_check::sacc}, Case{fix_at(0, 1.0, 1.5, 0.2, 5), gnss_check::nsats}}) {
    GnssChecks c;
    for (int i = 0; i < 200; ++i) {
      msg::Gnss g = k.g;
      g.stamp = from_seconds(0.1 * i);
      c.update(g, true, Motion::at_rest);
    }
    CHECK_FALSE(c.passed());
    CHECK(c.failing() == k.bit);
    CHECK_FALSE(c.describe_failing().empty());
    // the same check disabled in the mask (EKF2_GPS_CHECK) passes after the hold
    GnssCheckConfig cfg;
    cfg.mask &= ~static_cast<std::int64_t>(k.bit);
    GnssChecks off(cfg);
    CHECK(passed_near(feed(off, 0.0, 11.0, Motion::at_rest,
                           [&](double t) {
                             msg::Gnss g = k.g;
                             g.stamp = from_seconds(t);
                             return g;
                           }),
                      10.0));
  }
  // nothing reported (accuracies 0, no satellite count): passes
  GnssChecks none;
  CHECK(passed_near(feed(none, 0.0, 11.0, Motion::at_rest, [](double t) { return fix_at(t, 0.0, 0.0, 0.0, 0); }), 10.0));
  // a fix below min_fix_type fails (not maskable) and restarts the hold
  GnssChecks c;
  feed(c, 0.0, 8.0, Motion::at_rest, [](double t) { return fix_at(t); });
  msg::Gnss no_fix = fix_at(8.1);
  no_fix.fix_type = msg::FixType::fix_2d;
  c.update(no_fix, false, Motion::at_rest);
  CHECK(c.failing() == gnss_check::fix);
  CHECK(passed_near(feed(c, 8.2, 20.0, Motion::at_rest, [](double t) { return fix_at(t); }), 18.1));
}

TEST_CASE("GNSS checks: a log with dilutions and no accuracies: PDOP (PX4) from both, HDOP (ArduPilot) from one alone") {
  const auto dop_fix = [](double t, double hdop, double vdop) {
    msg::Gnss g = fix_at(t, 0.0, 0.0, 0.0, 0);  // no accuracy, no satellite count reported
    g.hdop = hdop;
    g.vdop = vdop;
    return g;
  };
  // PDOP = sqrt(1.8^2 + 2.0^2) = 2.69 > 2.5 although each alone is below it
  GnssChecks both;
  CHECK(feed(both, 0.0, 20.0, Motion::at_rest, [&](double t) { return dop_fix(t, 1.8, 2.0); }) < 0.0);
  CHECK(both.failing() == gnss_check::pdop);
  CHECK(both.describe_failing() == "PDOP 2.69 > 2.50");
  // HDOP alone: 3.1 fails, then the geometry improves to 1.2 and the hold runs from there
  GnssChecks alone;
  CHECK(feed(alone, 0.0, 15.0, Motion::at_rest, [&](double t) { return dop_fix(t, 3.1, 0.0); }) < 0.0);
  CHECK(alone.describe_failing() == "HDOP 3.10 > 2.50");
  CHECK(passed_near(feed(alone, 15.1, 30.0, Motion::at_rest, [&](double t) { return dop_fix(t, 1.2, 0.0); }), 25.0));
  // a limit raised (gnss_req_pdop) lets the first receiver through; 0 (not reported) passes
  GnssCheckConfig loose;
  loose.max_pdop = 3.0;
  GnssChecks relaxed(loose), unreported;
  CHECK(passed_near(feed(relaxed, 0.0, 11.0, Motion::at_rest, [&](double t) { return dop_fix(t, 1.8, 2.0); }), 10.0));
  CHECK(passed_near(feed(unreported, 0.0, 11.0, Motion::at_rest, [&](double t) { return dop_fix(t, 0.0, 0.0); }), 10.0));
}

TEST_CASE("GNSS checks: drift while still fails without any reported accuracy; moving keeps the verdict; flying passes it") {
  // climbing 1 m/s in the receiver's altitude and velocity, nothing else reported
  const auto drifting = [](double t) {
    msg::Gnss g = fix_at(t, 0.0, 0.0, 0.0, 0);
    g.alt += 1.0 * t;
    g.vel.z() = -1.0;
    return g;
  };
  GnssChecks c;
  CHECK(feed(c, 0.0, 30.0, Motion::at_rest, drifting) < 0.0);
  CHECK(c.failing() == (gnss_check::vdrift | gnss_check::vspeed));
  CHECK(c.v_drift() > 0.5);
  CHECK(c.v_speed() > 0.5);
  std::printf("GNSS checks, a receiver climbing 1 m/s at rest: %s\n", c.describe_failing().c_str());
  // carried (moving on the ground): the filters stop, the verdicts stay
  CHECK(feed(c, 30.1, 60.0, Motion::moving, drifting) < 0.0);
  CHECK(c.failing() == (gnss_check::vdrift | gnss_check::vspeed));
  // in the air the drift checks pass: the hold from the first fix in the air
  CHECK(passed_near(feed(c, 60.1, 80.0, Motion::in_air, drifting), 70.0));
  // horizontally: 0.3 m/s east
  GnssChecks h;
  CHECK(feed(h, 0.0, 30.0, Motion::at_rest, [](double t) {
          msg::Gnss g = fix_at(t, 0.0, 0.0, 0.0, 0);
          g.lon += 0.3 * t / 75500.0;  // about 75.5 km per degree of longitude at 47.4 deg
          g.vel.y() = 0.3;
          return g;
        }) < 0.0);
  CHECK(h.failing() == (gnss_check::hdrift | gnss_check::hspeed));
  CHECK(h.h_drift() > 0.25);  // 0.3 m/s through 30 s of a 10-s low-pass from 0: 0.285
  CHECK(h.h_drift() < 0.32);
}

namespace {

/// A settling receiver on an aircraft at rest (the log: 3 m/s of vertical speed and an
/// altitude tens of metres off, settling over tens of seconds): its altitude off by
/// 18 exp(-t/6) m plus a 2-m, 7-s wander that dies out, the vertical velocity that goes with it,
/// its accuracies shrinking from 10 m (h), 25 m (v), 2 m/s to 0.8, 1, 0.1; or, with `report`
/// false, no accuracies and no satellite count at all (the Zurich 2014 log's receiver).
struct SettlingReceiver {
  bool report = true;
  double offset(double t) const { return 18.0 * std::exp(-t / 6.0) + 2.0 * std::sin(2.0 * kPi * t / 7.0) * std::exp(-t / 10.0); }
  double climb(double t) const {  // d offset / dt, m/s
    return -3.0 * std::exp(-t / 6.0) +
           2.0 * std::exp(-t / 10.0) * (2.0 * kPi / 7.0 * std::cos(2.0 * kPi * t / 7.0) - 0.1 * std::sin(2.0 * kPi * t / 7.0));
  }
  bool operator()(msg::Gnss& g) const {
    const double t = to_seconds(g.stamp), e = std::exp(-t / 6.0);
    g.alt += offset(t);
    g.vel.z() -= climb(t);
    g.h_acc = report ? 0.8 + 10.0 * e : 0.0;
    g.v_acc = report ? 1.0 + 25.0 * e : 0.0;
    g.s_acc = report ? 0.1 + 2.0 * e : 0.0;
    if (!report) g.num_sats = 0;
    return true;
  }
};

struct Start {
  Vec3 origin_error;       ///< origin - the settled receiver's position at the aircraft, NED m
  double b_baro = 0.0;     ///< the filter's barometer bias at the end, m
  double alt_error = 0.0;  ///< the estimate's down position - the truth's (in the estimate's frame) at the end, m
  double e_gnss = 0.0;     ///< the filter's vertical GNSS error state at the end, m
  double wait = -1.0;      ///< s from the first fix to the origin
  bool initialized = false;
};

Start start_on(const SettlingReceiver& rx, const EstimatorConfig& cfg, double seconds) {
  SimOptions o;
  o.static_mode = true;
  o.wind.setZero();
  o.gnss_h = 0.2;
  o.gnss_v = 0.3;
  TruthSim sim(o);
  Estimator est(cfg);
  Hooks h;
  h.gnss = [&](msg::Gnss& g) { return rx(g); };
  fly(sim, est, seconds, h);
  Start s;
  s.initialized = est.initialized();
  if (!est.origin_valid()) return s;
  const msg::State st = est.state();
  s.origin_error = sim.ned_of(st.origin_lat, st.origin_lon, st.origin_alt) - sim.truth().p;
  s.b_baro = est.filter().x().b_baro;
  s.alt_error = st.p_d - truth_position(sim.truth(), est, sim).z();
  s.e_gnss = est.filter().x().e_gnss.z();
  for (const Event& e : est.take_events())
    if (e.kind == EventKind::gnss_checks_passed) s.wait = e.value;
  return s;
}

}  // namespace

TEST_CASE("a settling receiver at rest: the origin and the barometer's datum come from the settled fixes") {
  EstimatorConfig checked = truth_sim_config();
  checked.gnss_checks = GnssCheckConfig{};  // PX4's checks and hold
  EstimatorConfig first_fix = truth_sim_config();
  first_fix.gnss_checks.mask = 0;  // the origin on the first fix, as before the checks
  for (const bool report : {true, false}) {
    SettlingReceiver rx;
    rx.report = report;
    const Start a = start_on(rx, checked, 90.0), b = start_on(rx, first_fix, 90.0);
    std::printf(
        "settling receiver (%s): origin after %.1f s, off by %.2f m vertically (first fix: %.2f m); "
        "baro bias %.2f m (first fix: %.2f m), altitude error %.2f m (first fix: %.2f m), GNSS error state %.2f m (first fix: %.2f m)\n",
        report ? "accuracies reported" : "nothing reported", a.wait, a.origin_error.z(), b.origin_error.z(), a.b_baro, b.b_baro,
        a.alt_error, b.alt_error, a.e_gnss, b.e_gnss);
    REQUIRE(a.initialized);
    CHECK(a.wait > 10.0);
    // from the settled fixes: within the receiver's own error (0.3 m vertical, 0.2 m horizontal, 3 sigma)
    CHECK(std::fabs(a.origin_error.z()) < 1.0);
    CHECK(a.origin_error.head<2>().norm() < 1.0);
    // the barometer calibrated against that datum: the filter's altitude, the barometer and the
    // GNSS agree (no bias, no GNSS error taken up)
    CHECK(std::fabs(a.b_baro) < 1.0);
    CHECK(std::fabs(a.alt_error) < 1.0);
    CHECK(std::fabs(a.e_gnss) < 1.0);
    // the first fix is 18 m off, and the barometer's datum with it: a minute later the filter
    // still holds much of the barometer's altitude and explains the settled fixes as a GNSS error
    // (less of it where the receiver reports its accuracy improving: gnss_constellation_jumps)
    CHECK(std::fabs(b.origin_error.z()) > 15.0);
    CHECK(std::fabs(b.alt_error) > 5.0);
    CHECK(std::fabs(b.e_gnss) > 5.0);
  }
}

TEST_CASE("a receiver that never settles: no origin, no estimate, the failing check reported") {
  EstimatorConfig cfg = truth_sim_config();
  cfg.gnss_checks = GnssCheckConfig{};
  SimOptions o;
  o.static_mode = true;
  TruthSim sim(o);
  Estimator est(cfg);
  Hooks h;
  h.gnss = [](msg::Gnss& g) {
    g.h_acc = 8.0;  // above EKF2_REQ_EPH's 3 m for good
    return true;
  };
  fly(sim, est, 60.0, h);
  CHECK_FALSE(est.origin_valid());
  CHECK_FALSE(est.initialized());
  CHECK_FALSE(est.state().valid);
  CHECK(est.gnss_checks().failing() == gnss_check::eph);
  CHECK(est.gnss_position_model().stats.accepted == 0);
  CHECK(est.baro_model().stats.accepted == 0);
  int failing_events = 0;
  for (const Event& e : est.take_events()) {
    CHECK(e.kind != EventKind::baro_calibrated);
    if (e.kind == EventKind::gnss_checks_failing) {
      ++failing_events;
      CHECK(describe(e) == "gnss: waiting for the receiver to settle: h_acc");
    }
  }
  CHECK(failing_events == 1);  // reported once: it never changed
}

TEST_CASE("a check failing within the hold drops the start: origin, estimate and barometer calibration begin again") {
  EstimatorConfig cfg = truth_sim_config();
  cfg.gnss_checks = GnssCheckConfig{};
  SimOptions o;
  o.static_mode = true;
  TruthSim sim(o);
  Estimator est(cfg);
  Hooks h;
  h.gnss = [&](msg::Gnss& g) {
    const double t = to_seconds(g.stamp);
    if (t > 4.95 && t < 5.05) g.h_acc = 10.0;  // one fix at 5 s above EKF2_REQ_EPH
    return true;
  };
  fly(sim, est, 4.9, h);
  CHECK(est.initialized());         // started on the first passing fix...
  CHECK_FALSE(est.origin_valid());  // ...provisionally: invalid on the ground until the hold
  CHECK_FALSE(est.state().valid);
  fly(sim, est, 0.12, h);  // the fix at 5 s
  CHECK_FALSE(est.initialized());
  fly(sim, est, 9.78, h);  // to 14.9 s: the start again at 5.1 s, the hold from the failure at 5 s
  CHECK(est.initialized());
  CHECK_FALSE(est.state().valid);
  fly(sim, est, 0.3, h);
  CHECK(est.origin_valid());
  CHECK(est.state().valid);
  int set = 0, dropped = 0, calibrated = 0;
  for (const Event& e : est.take_events()) {
    set += e.kind == EventKind::origin_set;
    dropped += e.kind == EventKind::origin_dropped;
    calibrated += e.kind == EventKind::baro_calibrated;
  }
  CHECK(set == 2);
  CHECK(dropped == 1);
  CHECK(calibrated == 2);
}

TEST_CASE("a fix from fewer satellites moves the GNSS error state, not the position (gnss_constellation_jumps)") {
  // From 60 to 90 s the receiver keeps 5 satellites: it reports 4 m / 6 m and its solution is
  // 5 m north and 6 m up of the whole sky's (within 1.5 of its new accuracies); at 90 s the sky returns.
  struct Outcome {
    double worst_h = 0.0, worst_v = 0.0, after = 0.0;
    std::uint64_t resets = 0, jumps = 0;
  };
  const auto run = [](bool jumps) {
    EstimatorConfig cfg = truth_sim_config();
    cfg.gnss_constellation_jumps = jumps;
    TruthSim sim(SimOptions{});
    Estimator est(cfg);
    Hooks h;
    h.gnss = [](msg::Gnss& g) {
      const double t = to_seconds(g.stamp);
      if (t >= 60.0 && t < 90.0) {
        g.num_sats = 5;
        g.h_acc = 4.0;
        g.v_acc = 6.0;
        const GeoPoint moved = GeoOrigin(g.lat, g.lon, g.alt).to_geodetic(Eigen::Vector3d(5.0, 0.0, -6.0));
        g.lat = moved.lat;
        g.alt = moved.alt;
      }
      return true;
    };
    Outcome r;
    fly(sim, est, 120.0, h, [&](const Truth& t, const Estimator& e) {
      if (to_seconds(sim.now()) < 60.0 || !e.initialized()) return;
      const Eigen::Vector3d d = e.filter().x().p - truth_position(t, e, sim);
      r.worst_h = std::max(r.worst_h, d.head<2>().norm());
      r.worst_v = std::max(r.worst_v, std::fabs(d.z()));
      r.after = d.norm();
    });
    r.resets = est.gnss_resets();
    r.jumps = est.constellation_jumps();
    return r;
  };
  const Outcome on = run(true), off = run(false);
  std::printf(
      "5 satellites for 30 s, the fix 5 m north, 6 m up: worst error %.2f m horizontal, %.2f m vertical, %.2f m at 120 s "
      "(%llu jumps; without the jumps %.2f, %.2f, %.2f m, %llu GNSS resets)\n",
      on.worst_h, on.worst_v, on.after, static_cast<unsigned long long>(on.jumps), off.worst_h, off.worst_v, off.after,
      static_cast<unsigned long long>(off.resets));
  CHECK(on.jumps == 2);
  CHECK(on.resets == 0);
  // the jump went into e_gnss: the position held within 2 m of the truth ...
  CHECK(on.worst_h < 2.0);
  CHECK(on.worst_v < 2.5);
  CHECK(on.after < 1.0);
  // ... where without the jump model the fixes pulled it along
  CHECK(off.worst_h > on.worst_h + 1.0);
}
