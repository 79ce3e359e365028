#include "safety/phase_machine.hpp"

#include <cmath>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

namespace tern::core {

void PhaseMachine::configure() {
  declare(state_, "state", "vehicle state (altitude)");
  declare(command_, "controller_command", "commanded altitude h_c", Need::optional);
  declare(fcu_, "fcu_status", "flight-control unit status: the flight waits disarmed until it is armed and error-free", Need::optional);
  declare(innovations_, "innovations", "estimator innovation test ratios (preflight check)", Need::optional);
  declare(gnss_, "gnss", "GNSS fix quality (preflight check)", Need::optional);
  declare(rc_, "rc", "RC receiver (preflight check when preflight_require_rc)", Need::optional);
  declare(path_, "current_path", "the path manager's segment: a land item's glide path (approach, flare, rollout)", Need::optional);
  declare(range_, "range", "downward range finder: the height above the runway on the landing (absent: the altitude estimate's)",
          Need::optional);
  declare(phase_out_, "flight_phase", "current flight phase");
  declare(alt_toz_, "alt_toz", 5.0,
          ParamSpec("m", 0.0, 1000.0, "top of the takeoff zone: climb begins above this altitude (ROSplane alt_toz)"));
  declare(alt_hz_, "alt_hz", 20.0,
          ParamSpec("m", 0.1, 1000.0, "altitude-hold zone half-width around h_c: cruise within it (ROSplane alt_hz)"));
  declare(max_deflection_, "max_deflection", 0.7,
          ParamSpec("rad", 0.01, 3.2, "a controller commanding a larger surface deflection is replaced by the fallback"));
  declare_preflight();
  declare_safety();
  declare_recovery();
  declare_landing();
  declare_takeoff();
  declare(min_phase_time_, "min_phase_time", 1.0,
          ParamSpec("s", 0.0, 60.0, "a transition back (loss of altitude) needs its condition this long"));
}

void PhaseMachine::declare_preflight() {
  const PreflightLimits d;
  declare(preflight_, "preflight", true, ParamSpec("", 0, 0, "hold on the ground (motor off) until the arming checks pass").start_only());
  declare(preflight_time_, "preflight_time", 2.0, ParamSpec("s", 0.0, 600.0, "the arming checks must all pass this long"));
  declare(preflight_timeout_, "preflight_timeout", 120.0,
          ParamSpec("s", 1.0, 3600.0, "end the flight (preflight_failed) if not armed by then"));
  declare(report_interval_, "preflight_report_interval", 5.0, ParamSpec("s", 0.1, 600.0, "how often the failing checks are logged"));
  declare(max_tilt_sigma_, "preflight_max_tilt_sigma", d.max_tilt_sigma, ParamSpec("rad", 1e-4, 1.0, "estimator roll/pitch 1-sigma limit"));
  declare(max_yaw_sigma_, "preflight_max_yaw_sigma", d.max_yaw_sigma, ParamSpec("rad", 1e-4, 3.2, "estimator yaw 1-sigma limit"));
  declare(max_gyro_bias_sigma_, "preflight_max_gyro_bias_sigma", d.max_gyro_bias_sigma,
          ParamSpec("rad/s", 1e-5, 1.0, "estimator gyro-bias 1-sigma limit, per axis"));
  declare(max_position_sigma_, "preflight_max_position_sigma", d.max_position_sigma,
          ParamSpec("m", 0.01, 1000.0, "estimator horizontal position 1-sigma limit"));
  declare(max_h_acc_, "preflight_max_h_acc", d.max_h_acc, ParamSpec("m", 0.01, 1000.0, "GNSS reported horizontal accuracy limit"));
  declare(max_v_acc_, "preflight_max_v_acc", d.max_v_acc, ParamSpec("m", 0.01, 1000.0, "GNSS reported vertical accuracy limit"));
  declare(min_sats_, "preflight_min_sats", std::int64_t{d.min_sats}, ParamSpec("", 0, 64, "GNSS satellites in use, at least"));
  declare(max_ground_speed_, "preflight_max_ground_speed", d.max_ground_speed,
          ParamSpec("m/s", 0.0, 100.0, "the aircraft counts as at rest below this"));
  declare(require_rc_, "preflight_require_rc", d.require_rc, ParamSpec("", 0, 0, "the pilot's transmitter must be heard before takeoff"));
  declare(max_rc_age_, "preflight_max_rc_age", d.max_rc_age, ParamSpec("s", 0.01, 60.0, "the newest RC frame at most this old"));
  declare(max_wind_, "preflight_max_wind", d.max_wind,
          ParamSpec("m/s", 0.0, 100.0, "the wind seen at rest (airspeed, estimated wind) above this: no takeoff"));
}

// The phase router's safety monitor (safety_monitor.hpp; each default's reason is there).
void PhaseMachine::declare_safety() {
  const SafetyLimits d;
  declare(safety_, "safety", d.enabled,
          ParamSpec("", 0, 0, "the safety monitor may engage the fallback (silent controller, envelope, saturation)"));
  declare(safety_hand_back_, "safety_hand_back", false,
          ParamSpec("", 0, 0, "after a safety engagement the next phase change hands back to the phase's controller"));
  declare(safety_silent_periods_, "safety_silent_periods", d.silent_periods,
          ParamSpec("", 1, 1000, "steps in a row without an actuators message before the fallback takes over"));
  declare(safety_hold_, "safety_hold", d.hold, ParamSpec("s", 0.0, 10.0, "an envelope limit must be exceeded this long (hysteresis)"));
  declare(safety_roll_max_, "safety_roll_max", d.roll_max, ParamSpec("rad", 0.1, 3.2, "envelope: |roll| above this"));
  declare(safety_pitch_max_, "safety_pitch_max", d.pitch_max, ParamSpec("rad", 0.0, 1.6, "envelope: pitch above this"));
  declare(safety_pitch_min_, "safety_pitch_min", d.pitch_min, ParamSpec("rad", -1.6, 0.0, "envelope: pitch below this"));
  declare(safety_floor_, "safety_floor", d.floor,
          ParamSpec("m", -1000.0, 10000.0, "envelope (climb, cruise): altitude above the origin below this"));
  declare(safety_airspeed_min_, "safety_airspeed_min", d.airspeed_min,
          ParamSpec("m/s", 0.0, 200.0, "envelope (climb, cruise): airspeed below this (stall margin)"));
  declare(safety_airspeed_max_, "safety_airspeed_max", d.airspeed_max,
          ParamSpec("m/s", 1.0, 400.0, "envelope (climb, cruise): airspeed above this (Vne)"));
  declare(safety_sink_max_, "safety_sink_max", d.sink_max,
          ParamSpec("m/s", 0.1, 200.0, "envelope (climb, cruise): sink rate v_d above this"));
  declare(safety_saturation_, "safety_saturation", d.saturation,
          ParamSpec("", 0.5, 1.0, "a surface beyond this fraction of max_deflection is at its stop"));
  declare(safety_error_growth_, "safety_error_growth", d.error_growth,
          ParamSpec("m", 0.1, 1000.0, "delta_e (or delta_t at 0) at its stop while the altitude error grows by this much"));
}

// The phase router's state-loss recovery (state_loss_recovery.hpp; each default's reason is there).
void PhaseMachine::declare_recovery() {
  const RecoveryGains d;
  declare(recovery_, "recovery", true,
          ParamSpec("", 0, 0, "the built-in state-loss recovery flies while the estimate is invalid (climb, cruise)"));
  declare(recovery_trim_tau_, "recovery_trim_tau", d.trim_tau,
          ParamSpec("s", 0.01, 600.0, "time constant of the trim: the average good command"));
  declare(recovery_throttle_up_, "recovery_throttle_up", d.throttle_up,
          ParamSpec("", 0.0, 1.0, "throttle added to the trim (a gentle climb)"));
  declare(recovery_roll_kp_, "recovery_roll_kp", d.roll_kp, ParamSpec("rad/rad", 0.0, 10.0, "aileron per rad of roll (integrated gyro)"));
  declare(recovery_roll_kd_, "recovery_roll_kd", d.roll_kd, ParamSpec("rad/(rad/s)", 0.0, 10.0, "aileron per rad/s of roll rate (gyro)"));
}

// The landing's decisions (landing_checks.hpp; each default's reason is there).
void PhaseMachine::declare_landing() {
  const LandingLimits d;
  declare(land_max_cross_track_, "land_max_cross_track", d.max_cross_track,
          ParamSpec("m", 0.1, 1000.0, "stabilised approach: cross-track error at most this below the decision height"));
  declare(land_max_glide_error_, "land_max_glide_error", d.max_glide_error,
          ParamSpec("m", 0.1, 1000.0, "stabilised approach: altitude within this of the glide path below the decision height"));
  declare(land_max_airspeed_deficit_, "land_max_airspeed_deficit", d.max_airspeed_deficit,
          ParamSpec("m/s", 0.1, 100.0, "stabilised approach: airspeed at most this below the commanded airspeed"));
  declare(land_ground_band_, "land_ground_band", d.ground_band,
          ParamSpec("m", 0.0, 20.0, "flare -> rollout: within this height of the touchdown point a stopped sink is the ground"));
  declare(land_stopped_speed_, "land_stopped_speed", d.stopped_speed,
          ParamSpec("m/s", 0.01, 10.0, "rollout -> stopped: ground speed below this (for land_stopped_time)"));
  declare(land_stopped_time_, "land_stopped_time", d.stopped_time, ParamSpec("s", 0.0, 60.0, "rollout -> stopped: stopped this long"));
}

// The takeoff's abort criteria (takeoff_checks.hpp; each default's reason is there).
void PhaseMachine::declare_takeoff() {
  const TakeoffLimits d;
  declare(takeoff_run_length_, "takeoff_run_length", d.run_length,
          ParamSpec("m", 1.0, 10000.0, "abort the takeoff when the airspeed has not reached takeoff_min_airspeed after this run"));
  declare(takeoff_min_airspeed_, "takeoff_min_airspeed", d.min_airspeed,
          ParamSpec("m/s", 0.0, 200.0, "airspeed the takeoff run must reach within takeoff_run_length"));
  declare(takeoff_max_roll_, "takeoff_max_roll", d.max_roll, ParamSpec("rad", 0.05, 3.2, "abort the takeoff: |roll| above this"));
  declare(takeoff_max_pitch_, "takeoff_max_pitch", d.max_pitch, ParamSpec("rad", 0.05, 1.6, "abort the takeoff: pitch above this"));
  declare(takeoff_min_pitch_, "takeoff_min_pitch", d.min_pitch, ParamSpec("rad", -1.6, 0.0, "abort the takeoff: pitch below this"));
  declare(takeoff_safe_height_, "takeoff_safe_height", d.safe_height,
          ParamSpec("m", 0.0, 1000.0, "the takeoff's attitude limits apply below this height above its start"));
}

TakeoffLimits PhaseMachine::takeoff_limits() const {
  TakeoffLimits l;
  l.run_length = takeoff_run_length_();
  l.min_airspeed = takeoff_min_airspeed_();
  l.max_roll = takeoff_max_roll_();
  l.max_pitch = takeoff_max_pitch_();
  l.min_pitch = takeoff_min_pitch_();
  l.safe_height = takeoff_safe_height_();
  return l;
}

LandingLimits PhaseMachine::landing_limits() const {
  LandingLimits l;
  l.max_cross_track = land_max_cross_track_();
  l.max_glide_error = land_max_glide_error_();
  l.max_airspeed_deficit = land_max_airspeed_deficit_();
  l.ground_band = land_ground_band_();
  l.stopped_speed = land_stopped_speed_();
  l.stopped_time = land_stopped_time_();
  return l;
}

RecoveryGains PhaseMachine::recovery_gains() const {
  RecoveryGains g;
  g.trim_tau = recovery_trim_tau_();
  g.throttle_up = recovery_throttle_up_();
  g.roll_kp = recovery_roll_kp_();
  g.roll_kd = recovery_roll_kd_();
  g.max_deflection = max_deflection_();
  return g;
}

SafetyLimits PhaseMachine::safety_limits() const {
  SafetyLimits l;
  l.enabled = safety_();
  l.silent_periods = safety_silent_periods_();
  l.hold = safety_hold_();
  l.roll_max = safety_roll_max_();
  l.pitch_max = safety_pitch_max_();
  l.pitch_min = safety_pitch_min_();
  l.floor = safety_floor_();
  l.airspeed_min = safety_airspeed_min_();
  l.airspeed_max = safety_airspeed_max_();
  l.sink_max = safety_sink_max_();
  l.max_deflection = max_deflection_();
  l.saturation = safety_saturation_();
  l.error_growth = safety_error_growth_();
  return l;
}

std::optional<double> PhaseMachine::commanded_altitude() const {
  if (!command_.has_value() || !std::isfinite(command_->h_c)) return std::nullopt;
  return command_->h_c;
}

std::optional<double> PhaseMachine::commanded_airspeed() const {
  if (!command_.has_value() || !std::isfinite(command_->Va_c)) return std::nullopt;
  return command_->Va_c;
}

PreflightLimits PhaseMachine::limits() const {
  PreflightLimits l;
  l.max_tilt_sigma = max_tilt_sigma_();
  l.max_yaw_sigma = max_yaw_sigma_();
  l.max_gyro_bias_sigma = max_gyro_bias_sigma_();
  l.max_position_sigma = max_position_sigma_();
  l.max_h_acc = max_h_acc_();
  l.max_v_acc = max_v_acc_();
  l.min_sats = static_cast<int>(min_sats_());
  l.max_ground_speed = max_ground_speed_();
  l.require_rc = require_rc_();
  l.max_rc_age = max_rc_age_();
  l.max_wind = max_wind_();
  return l;
}

void PhaseMachine::start() {
  reset();
  if (preflight_()) {
    preflight_skip_warned_ = false;
  } else {
    constexpr const char* kSkipped = "preflight skipped: the takeoff begins at t = 0 on whatever the estimator has";
    if (std::exchange(preflight_skip_warned_, true))
      log().info("{} (as in this host's earlier flights)", kSkipped);
    else
      log().warn("{}", kSkipped);
  }
}

void PhaseMachine::reset() {
  f_ = Flight{};
  f_.phase = first_phase();
  msg::FlightPhase m;
  m.phase = m.previous = f_.phase;
  phase_out_.publish(m);
}

void PhaseMachine::enter(Nanos now, msg::Phase to, std::string reason) {
  log().info("phase {} -> {} at t={:.3f} s: {}", msg::phase_name(f_.phase), msg::phase_name(to), to_seconds(now), reason);
  f_.transitions.push_back({now, f_.phase, to, std::move(reason)});
  msg::FlightPhase m;
  m.stamp = now;
  m.previous = f_.phase;
  m.phase = to;
  m.since = now;
  f_.phase = to;
  f_.since = now;
  f_.condition_since = -1;
  phase_out_.publish(m);
}

// After preflight (whose checks include the FCU's): a disarm waits, with no controller running.
bool PhaseMachine::wait_for_arming(Nanos now) {
  if (!fcu_.has_value() || f_.phase == msg::Phase::preflight) return false;
  const std::optional<std::string> not_ready = fcu_not_ready(*fcu_);
  if (!f_.disarmed && !fcu_->armed) {
    f_.disarmed = true;
    log().warn(
        "t={:.3f} s: flight waits disarmed (no takeoff, no controller running) until the FCU is armed and "
        "error-free: {}",
        to_seconds(now), *not_ready);
    f_.transitions.push_back({now, f_.phase, msg::Phase::takeoff, "disarmed: the FCU is not armed"});
    phase_out_.publish(msg::FlightPhase{now, msg::Phase::takeoff, f_.phase, now});
  } else if (f_.disarmed && !not_ready) {
    f_.disarmed = false;
    enter(now, msg::Phase::takeoff, "FCU armed and error-free: takeoff");
  }
  return f_.disarmed;
}

PreflightInputs PhaseMachine::preflight_inputs(Nanos now) const {
  PreflightInputs in;
  if (state_.has_value()) in.state = &state_.get();
  if (innovations_.has_value()) in.innovations = &innovations_.get();
  if (gnss_.has_value()) in.gnss = &gnss_.get();
  if (fcu_.has_value()) in.fcu = &fcu_.get();
  if (rc_.has_value()) in.rc_age = to_seconds(now - rc_->stamp);
  return in;
}

void PhaseMachine::run_preflight(Nanos now) {
  const PreflightInputs in = preflight_inputs(now);
  const std::vector<std::string> failing = preflight_failures(in, limits());
  if (failing.empty()) {
    if (f_.checks_passed_since < 0) f_.checks_passed_since = now;
    if (now - f_.checks_passed_since >= from_seconds(preflight_time_()))
      enter(
          now, msg::Phase::takeoff,
          fmt::format("arming checks passed for {:.1f} s (aligned at t={:.3f} s)", preflight_time_(), to_seconds(f_.checks_passed_since)));
    return;
  }
  f_.checks_passed_since = -1;
  const bool armed = in.fcu == nullptr || in.fcu->armed;
  if (!armed) f_.preflight_since = -1;  // the time-out counts once the FCU is armed: arming late is no failure
  if (armed && f_.preflight_since < 0) f_.preflight_since = now;
  if (armed && now - f_.preflight_since >= from_seconds(preflight_timeout_())) {
    f_.failure = "preflight_failed: " + fmt::format("{}", fmt::join(failing, "; "));
    return;
  }
  if (f_.last_report >= 0 && now - f_.last_report < from_seconds(report_interval_())) return;
  f_.last_report = now;
  // A preflight waits for the FCU's calibration and the estimator's alignment (seconds): what it
  // waits for is information; a warning once the armed FCU has waited half of preflight_timeout.
  const bool long_wait = armed && now - f_.preflight_since >= from_seconds(0.5 * preflight_timeout_());
  for (const std::string& f : failing) {
    if (long_wait)
      log().warn("t={:.3f} s: not taking off: {}", to_seconds(now), f);
    else
      log().info("t={:.3f} s: not taking off yet: {}", to_seconds(now), f);
  }
}

void PhaseMachine::go_around(Nanos now, const std::string& why) {
  ++f_.go_arounds;
  enter(now, msg::Phase::climb, "go-around: " + why);
}

std::string PhaseMachine::request_go_around(const std::string& source) {
  if (!msg::on_final(f_.phase))
    return fmt::format("no landing to go around from: the phase is {} (a go-around is taken on the approach and in the flare)",
                       msg::phase_name(f_.phase));
  f_.go_around_request = source;
  return "";
}

bool PhaseMachine::step_landing(Nanos now, const msg::State& s) {
  const bool on_path = path_.has_value() && path_->landing;
  const msg::Phase ph = f_.phase;
  if (!f_.go_around_request.empty()) {
    const std::string source = std::exchange(f_.go_around_request, "");
    if (msg::on_final(ph)) {
      go_around(now, fmt::format("the operator's command ({})", source));
      return true;
    }
  }
  if ((ph == msg::Phase::climb || ph == msg::Phase::cruise) && on_path && path_->attempt != f_.approach_seen) {
    f_.approach_seen = path_->attempt;
    enter(now, msg::Phase::approach, fmt::format("final approach {} of the land item", path_->attempt));
    return true;
  }
  if (ph == msg::Phase::rollout) {
    step_rollout(now, s);
    return true;
  }
  if (!msg::on_final(ph)) return false;
  if (!on_path) {
    if (ph == msg::Phase::approach) go_around(now, "the glide path was left (the mission changed)");
    return true;  // a flare goes on: the aircraft is committed
  }
  const msg::CurrentPath& p = *path_;
  const double h = runway_height(s, p, range_.has_value() ? &range_.get() : nullptr, now);
  if (ph == msg::Phase::flare) {
    const LandingLimits l = landing_limits();
    const bool settled = h < l.ground_band && std::fabs(s.v_d) < l.settled_sink;
    if (!settled) f_.condition_since = -1;
    if (settled && f_.condition_since < 0) f_.condition_since = now;
    if (settled && now - f_.condition_since >= from_seconds(l.settled_time))
      enter(now, msg::Phase::rollout, fmt::format("on the wheels: {:.2f} m above the touchdown point, sink {:.2f} m/s", h, s.v_d));
  } else if (h < p.flare_height) {
    enter(now, msg::Phase::flare, fmt::format("{:.1f} m above the touchdown point (flare height {:.1f} m)", h, p.flare_height));
  } else if (const double along = along_touchdown(s, p); along > 0.0 && h < p.decision_height) {
    // the glide path ended above the runway (the estimate's altitude metres off): flare from here
    enter(now, msg::Phase::flare,
          fmt::format("{:.1f} m past the touchdown point, {:.1f} m above the runway: the glide path ended above it", along, h));
  } else if (h < p.decision_height) {
    const double Va_c = command_.has_value() && std::isfinite(command_->Va_c) ? command_->Va_c : s.Va;
    if (const std::string why = unstabilised(s, p, Va_c, landing_limits()); !why.empty())
      go_around(now, fmt::format("not stabilised at {:.1f} m (decision height {:.1f} m): {}", h, p.decision_height, why));
  }
  return true;
}

// Rollout (after a landing or an aborted takeoff): stopped once the ground speed stayed below
// land_stopped_speed for land_stopped_time; a landing then ends complete, an abort as a failure.
void PhaseMachine::step_rollout(Nanos now, const msg::State& s) {
  const LandingLimits l = landing_limits();
  if (std::hypot(s.v_n, s.v_e) >= l.stopped_speed) {
    f_.condition_since = -1;
    return;
  }
  if (f_.condition_since < 0) f_.condition_since = now;
  if (now - f_.condition_since < from_seconds(l.stopped_time)) return;
  if (!f_.abort_reason.empty()) {
    f_.failure = "takeoff_aborted: " + f_.abort_reason;
    enter(now, msg::Phase::stopped, "takeoff aborted, stopped");
    return;
  }
  std::string where;
  if (path_.has_value() && path_->landing) {
    const msg::CurrentPath& p = *path_;
    const double qn = std::max(std::hypot(p.q.x(), p.q.y()), 1e-9);
    const double dn = s.p_n - p.r.x(), de = s.p_e - p.r.y();
    where = fmt::format(", {:.1f} m along and {:.1f} m across the glide path's aim point (estimate), after {} approach(es)",
                        (dn * p.q.x() + de * p.q.y()) / qn, (-dn * p.q.y() + de * p.q.x()) / qn, p.attempt);
  }
  f_.landed_detail = fmt::format("stopped at t={:.3f} s{}", to_seconds(now), where);
  enter(now, msg::Phase::stopped, fmt::format("landed: ground speed below {:.1f} m/s for {:.1f} s", l.stopped_speed, l.stopped_time));
}

// Takeoff (and its climb, below takeoff_safe_height): abort on the run or the attitude
// (takeoff_checks.hpp); only for a takeoff begun at rest.
bool PhaseMachine::step_takeoff_checks(Nanos now, const msg::State& s) {
  const msg::Phase ph = f_.phase;
  if (ph == msg::Phase::takeoff && !f_.takeoff_start && std::isfinite(s.p_n) && std::isfinite(s.p_e)) {
    f_.takeoff_start = Eigen::Vector3d(s.p_n, s.p_e, s.p_d);
    f_.takeoff_checked = std::hypot(s.v_n, s.v_e) < max_ground_speed_();
  }
  if (!f_.takeoff_start || !f_.takeoff_checked || (ph != msg::Phase::takeoff && ph != msg::Phase::climb)) return false;
  const Eigen::Vector3d d = Eigen::Vector3d(s.p_n, s.p_e, s.p_d) - *f_.takeoff_start;
  const double height = -d.z();
  if (height >= takeoff_limits().safe_height) {
    f_.takeoff_checked = false;  // the takeoff is done: the climb and cruise safety nets watch from here
    return false;
  }
  const std::string why = takeoff_abort(s, d.head<2>().norm(), height, takeoff_limits());
  if (why.empty()) return false;
  f_.abort_reason = why;
  f_.takeoff_checked = false;
  enter(now, msg::Phase::rollout, "takeoff aborted: " + why + " (motor off, wings level, brakes)");
  return true;
}

std::vector<std::pair<std::string, double>> PhaseMachine::summary() const {
  return {{"go_arounds", static_cast<double>(f_.go_arounds)},
          {"landed", landed() ? 1.0 : 0.0},
          {"takeoff_aborted", f_.abort_reason.empty() ? 0.0 : 1.0}};
}

void PhaseMachine::step(Nanos now) {
  if (wait_for_arming(now)) return;
  if (f_.phase == msg::Phase::preflight) {
    run_preflight(now);
    return;
  }
  const msg::State& s = state_.get();
  if (!state_.has_value() || !std::isfinite(s.p_d)) return;
  if (step_takeoff_checks(now, s) || step_landing(now, s)) return;
  const double h = -s.p_d;
  const double h_c = command_.has_value() && std::isfinite(command_->h_c) ? command_->h_c : h;
  const Nanos dwell = from_seconds(min_phase_time_());
  auto held = [&](bool cond) {
    if (!cond) {
      f_.condition_since = -1;
      return false;
    }
    if (f_.condition_since < 0) f_.condition_since = now;
    return now - f_.condition_since >= dwell;
  };
  switch (f_.phase) {
    case msg::Phase::preflight: break;  // run_preflight()
    case msg::Phase::approach:
    case msg::Phase::flare:
    case msg::Phase::rollout:
    case msg::Phase::stopped: break;  // step_landing()
    case msg::Phase::takeoff:
      if (h >= alt_toz_()) enter(now, msg::Phase::climb, fmt::format("altitude {:.1f} m reached alt_toz {:.1f} m", h, alt_toz_()));
      break;
    case msg::Phase::climb:
      if (h < alt_toz_()) {
        if (held(true)) enter(now, msg::Phase::takeoff, fmt::format("altitude {:.1f} m fell below alt_toz {:.1f} m", h, alt_toz_()));
      } else if (std::fabs(h_c - h) < alt_hz_()) {
        enter(now, msg::Phase::cruise, fmt::format("altitude {:.1f} m within alt_hz {:.1f} m of h_c {:.1f} m", h, alt_hz_(), h_c));
      } else {
        held(false);
      }
      break;
    case msg::Phase::cruise:
    case msg::Phase::loiter:
    case msg::Phase::landing:
      if (h < alt_toz_()) {
        if (held(true)) enter(now, msg::Phase::takeoff, fmt::format("altitude {:.1f} m fell below alt_toz {:.1f} m", h, alt_toz_()));
      } else if (f_.phase == msg::Phase::cruise && h_c - h > alt_hz_()) {
        if (held(true))
          enter(now, msg::Phase::climb,
                fmt::format("altitude {:.1f} m is {:.1f} m below h_c {:.1f} m (more than alt_hz)", h, h_c - h, h_c));
      } else {
        held(false);
      }
      break;
  }
}

}  // namespace tern::core
