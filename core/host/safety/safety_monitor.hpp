// core/host/safety/safety_monitor.hpp: the phase router's safety monitor: when must the active
// controller give way to the fallback although every command it sends is finite and within the
// limits? Plain C++ on the standard messages (no host types), tested alone.
//
// After each step of the active controller the router calls check() with what that step did.
// A cause is returned (and the router engages the fallback) when, for `hold` seconds without a
// break (the hysteresis: a gust that rolls the aircraft past the limit for one tick is no cause):
//   silent      the controller stepped `silent_periods` times in a row without publishing
//               `actuators` (no hold: the count is its own time-out);
//   envelope    the estimate is valid and
//                 |phi| > roll_max, theta > pitch_max or theta < pitch_min   (rad)
//               or, in climb or cruise:
//                 Va < airspeed_min or Va > airspeed_max                      (m/s)
//                 v_d > sink_max                                              (m/s, down)
//               or, once the aircraft has been above `floor` in climb or cruise (whatever the
//               phase since, but for the landing's phases: the approach descends through it by
//               design, and a go-around re-arms it once above it again):
//                 h = -p_d < floor (m above the origin);
//   saturated   in climb or cruise, delta_e sits at its stop (|delta_e| >= saturation *
//               max_deflection), or delta_t at 0 with the aircraft below h_c and slower than Va_c
//               (short of energy both ways: the throttle should be up), while the altitude
//               error |h_c - h| has grown by more than error_growth (m) from its smallest since it got there (no
//               hold: the growth is its own filter). Full throttle is no cause (every climb),
//               nor the aileron (rolling into a turn grows the roll; the envelope catches a roll
//               that goes too far).
// The thresholds live in the phase machine's parameters (`phase_machine: {safety_roll_max: ..}`,
// see phase_machine.cpp for each default and its reason).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "tern/msg/all.hpp"
#include "tern/time.hpp"

namespace tern::core {

// The defaults, and why. The stock missions' extremes (seeds 1, 3, 7; estimate, takeoff to
// the end) are: |roll| 50 deg (66 in aggressive.yaml), pitch -24..+25 deg, airspeed in climb
// and cruise 12.7..23.4 m/s, sink rate 11.1 m/s (aggressive.yaml's dives), and no altitude below
// 10 m once past it: the defaults leave a margin beyond each.
struct SafetyLimits {
  bool enabled = true;
  /// 5 periods of a 100-Hz controller is 50 ms of frozen surfaces: one or two lost steps are
  /// no failure, and the servos (tau 20-50 ms) have barely moved.
  std::int64_t silent_periods = 5;
  /// s: a hard-over from cruise passes the pitch limit in under a second; 0.2 s lets a one-sample
  /// spike of the estimate (a GNSS correction) pass.
  double hold = 0.2;
  double roll_max = 1.31;       ///< rad (75 deg): aggressive.yaml's 66 deg plus a margin for gusts
  double pitch_max = 0.61;      ///< rad (35 deg): the 25-deg takeoff rotations plus 10 deg
  double pitch_min = -0.61;     ///< rad (-35 deg): aggressive.yaml's -24-deg dives plus 11 deg
  double floor = 8.0;           ///< m: above the takeoff zone (alt_toz 5 m), below every leg (70 m)
  double airspeed_min = 10.0;   ///< m/s: the anaconda rotates (lifts off) at 13 m/s; 3 m/s of stall margin below it
  double airspeed_max = 30.0;   ///< m/s: 7 m/s above the fastest stock dive (23.4); the anaconda has no published Vne
  double sink_max = 15.0;       ///< m/s: 4 m/s beyond aggressive.yaml's steepest descent (11.1)
  double max_deflection = 0.7;  ///< rad: the phase machine's max_deflection
  /// a surface beyond 95% of max_deflection is at its stop: slc's own elevator limit (max_e
  /// 0.61 rad) stays below it, a hard-over (0.69 of 0.7) does not
  double saturation = 0.95;
  /// m: the stock flights hold altitude within 1.2 m RMS, so 2 m more error with the elevator at
  /// its stop is no gust; the hard-over of tests/test_e2e_safety.cpp is caught 0.25 s before
  /// its pitch passes pitch_min, and the fallback pulls out 5 m higher than with 5 m
  double error_growth = 2.0;
};

/// What one step of the active controller left behind.
struct SafetyInputs {
  Nanos now = 0;
  msg::Phase phase = msg::Phase::takeoff;
  bool published = false;                     ///< the step published `actuators`
  const msg::Actuators* actuators = nullptr;  ///< the controller's latest command (nullptr: none yet)
  const msg::State* state = nullptr;          ///< the estimate (nullptr: none yet)
  std::optional<double> h_c;                  ///< commanded altitude, m (none: no command yet)
  std::optional<double> Va_c;                 ///< commanded airspeed, m/s (none: no command yet)
};

class SafetyMonitor {
 public:
  void set_limits(const SafetyLimits& l) { limits_ = l; }
  const SafetyLimits& limits() const { return limits_; }
  /// A new controller (or a new flight): counts and timers start again.
  void restart();
  /// The cause to engage the fallback, "" while the controller may go on.
  std::string check(const SafetyInputs& in);

 private:
  std::string silent(const SafetyInputs& in);
  /// The first envelope limit the estimate is beyond, "" if none.
  std::string envelope(const msg::State& s, msg::Phase phase);
  /// A surface at its stop with its error grown, "" if none.
  std::string saturated(const SafetyInputs& in);
  /// `why` has held since its first call without a break for `hold` s: returns it, else "".
  std::string held(Nanos now, std::string why, Nanos& since);

  SafetyLimits limits_;
  std::int64_t silent_steps_ = 0;
  Nanos envelope_since_ = -1;
  // the smallest error since each surface reached its stop (none: not at its stop)
  std::optional<double> sat_e_, sat_t_;
  bool floor_armed_ = false;  // the aircraft has been above the floor in climb or cruise
};

}  // namespace tern::core
