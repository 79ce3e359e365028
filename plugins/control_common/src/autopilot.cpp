#include "control_common/autopilot.hpp"

#include <cmath>

#include "tern/math.hpp"

namespace tern::control {

bool Command::finite() const {
  return std::isfinite(Va_c) && std::isfinite(h_c) && std::isfinite(chi_c) && std::isfinite(phi_ff) && std::isfinite(phi_c) &&
         std::isfinite(theta_c) && std::isfinite(h_td);
}

LongitudinalLaw::Output SlcLongitudinal::update(const VehicleState& x, const Command& c, bool /*climb*/, double dt) {
  Output o;
  o.theta_c = altitude_.update(c.h_c, x.h, x.h_dot, dt);
  o.delta_t = airspeed_.update(c.Va_c, x.Va, dt);
  o.delta_t_c = airspeed_.unsaturated();
  return o;
}

void SlcLongitudinal::initialise(const VehicleState& x, const Command& c, double theta_c, double delta_t) {
  altitude_.initialise(theta_c, c.h_c, x.h, x.h_dot);
  airspeed_.initialise(delta_t, c.Va_c, x.Va);
}

Surfaces Autopilot::limit(const Surfaces& u) const {
  const auto& L = lateral_.gains();
  const auto& P = pitch_.gains();
  return {saturate(u.delta_a, -L.max_a, L.max_a), saturate(u.delta_e, -P.max_e, P.max_e), saturate(u.delta_r, -L.max_r, L.max_r),
          saturate(u.delta_t, 0.0, 1.0)};
}

Surfaces Autopilot::trim() const { return limit({lateral_.gains().trim_a, pitch_.gains().trim_e, lateral_.gains().trim_r, 0.0}); }

void Autopilot::take_over(const Surfaces& last) {
  reset();
  f_.handover_from = last;
  f_.pending_handover = true;
  f_.last = AutopilotOutput{};
  f_.last.surfaces = last;
  f_.have_last = true;
}

void Autopilot::reset() {
  lateral_.reset();
  pitch_.reset();
  law_.reset();
  f_ = Flight{};
  f_.last.surfaces = trim();
}

AutopilotOutput Autopilot::update(Mode mode, const VehicleState& x, const Command& c, const Sticks& sticks_in, double dt) {
  const bool manual = mode == Mode::manual_passthrough || mode == Mode::manual_angle;
  const bool sticks_ok =
      std::isfinite(sticks_in.roll) && std::isfinite(sticks_in.pitch) && std::isfinite(sticks_in.yaw) && std::isfinite(sticks_in.throttle);
  if (!x.finite() || (!manual && !c.finite()) || (manual && !sticks_ok) || !std::isfinite(dt)) {
    AutopilotOutput held = f_.last;
    if (!f_.have_last) held.surfaces = trim();
    held.held = true;
    return held;
  }
  if (dt < 0.0) dt = 0.0;
  enter_mode(mode, x, c, !manual && c.override_phi, !manual && c.override_theta);
  const Sticks st{saturate(sticks_in.roll, -1.0, 1.0), saturate(sticks_in.pitch, -1.0, 1.0), saturate(sticks_in.yaw, -1.0, 1.0),
                  saturate(sticks_in.throttle, 0.0, 1.0)};
  AutopilotOutput out = mode == Mode::manual_passthrough ? passthrough(x, st) : loops(mode, x, c, st, dt);
  f_.last = out;
  f_.have_last = true;
  return out;
}

// A new mode or override: the handover starts from the last surfaces; the flare and the rollout
// take their initial conditions.
void Autopilot::enter_mode(Mode mode, const VehicleState& x, const Command& c, bool ovp, bool ovt) {
  if (mode != f_.mode || ovp != f_.override_phi || ovt != f_.override_theta) {
    if (f_.have_last && !f_.pending_handover) {
      f_.pending_handover = true;
      f_.handover_from = f_.last.surfaces;
    }
    if (mode != f_.mode) f_.rotated = false;
    if (mode == Mode::flare && f_.mode != Mode::flare) f_.flare.start(runway_height(x, c), -x.h_dot, x.theta, f_.last.surfaces.delta_t);
    if (mode == Mode::rollout && f_.mode != Mode::rollout) {
      f_.rollout_time = 0.0;
      f_.rollout_chi = x.chi;
    }
  }
  f_.mode = mode;
  f_.override_phi = ovp;
  f_.override_theta = ovt;
}

// manual_passthrough: the sticks straight to the surfaces; the loops restart from the pilot's
// command when the autopilot takes over again.
AutopilotOutput Autopilot::passthrough(const VehicleState& x, const Sticks& st) {
  const auto& L = lateral_.gains();
  const auto& P = pitch_.gains();
  AutopilotOutput out;
  out.surfaces = limit({st.roll * L.max_a, -st.pitch * P.max_e, -st.yaw * L.max_r, st.throttle});
  out.phi_c = x.phi;
  out.theta_c = x.theta;
  out.delta_t_c = st.throttle;
  lateral_.reset();
  pitch_.reset();
  law_.reset();
  f_.offset = {};
  f_.pending_handover = false;
  return out;
}

// Every mode but manual_passthrough: the roll and pitch loops, the speed law, the bumpless offset.
AutopilotOutput Autopilot::loops(Mode mode, const VehicleState& x, const Command& c, const Sticks& st, double dt) {
  const bool init = f_.pending_handover;
  const double h = init ? 0.0 : dt;  // the initialising step integrates nothing
  const LateralOut lat = lateral_step(mode, x, c, st, init, h);
  AutopilotOutput out;
  double delta_r = lat.delta_r;
  const LongitudinalOut lon = longitudinal_step(mode, x, c, st, init, h, delta_r, out.brake);
  // ---- bumpless offset
  const Surfaces raw{lat.delta_a, lon.delta_e, delta_r, lon.delta_t};
  if (init) {
    f_.offset = {f_.handover_from.delta_a - raw.delta_a, f_.handover_from.delta_e - raw.delta_e, f_.handover_from.delta_r - raw.delta_r,
                 f_.handover_from.delta_t - raw.delta_t};
    f_.pending_handover = false;
  } else if (dt > 0.0) {
    const double k = s_.handover_tau > 0.0 ? std::exp(-dt / s_.handover_tau) : 0.0;
    f_.offset = {f_.offset.delta_a * k, f_.offset.delta_e * k, f_.offset.delta_r * k, f_.offset.delta_t * k};
  }
  out.surfaces = limit(
      {raw.delta_a + f_.offset.delta_a, raw.delta_e + f_.offset.delta_e, raw.delta_r + f_.offset.delta_r, raw.delta_t + f_.offset.delta_t});
  out.phi_c = lat.phi_c;
  out.theta_c = lon.theta_c;
  out.delta_t_c = lon.delta_t_c;
  return out;
}

// Lateral: the roll command (course hold, a held angle, wings level), aileron and rudder.
Autopilot::LateralOut Autopilot::lateral_step(Mode mode, const VehicleState& x, const Command& c, const Sticks& st, bool init, double h) {
  const auto& L = lateral_.gains();
  const bool ovp = f_.override_phi;
  double phi_c = 0.0;
  bool use_course = false;
  if (mode == Mode::manual_angle) {
    phi_c = st.roll * s_.angle_roll_max;
  } else if (ovp) {
    phi_c = c.phi_c;
  } else if (mode == Mode::takeoff || mode == Mode::rollout || (mode == Mode::climb && !s_.climb_course_hold)) {
    phi_c = 0.0;
  } else {
    use_course = true;
  }
  // Bumpless transfer of the roll channel: with a roll-command slew limit the shaped command
  // restarts at the roll the last aileron implies and slews to the new command (the course
  // integrator starts clean); without one the course integrator absorbs the difference.
  const bool shaped_handover = init && L.roll_rate_max > 0.0;
  if (use_course) {
    if (init && !shaped_handover) {
      const double phi_needed = lateral_.roll_command_for(f_.handover_from.delta_a, x.phi, x.p);
      lateral_.initialise_course(phi_needed, c.chi_c, x.chi, x.r, c.phi_ff);
    }
    if (shaped_handover) lateral_.idle_course();
    phi_c = lateral_.course(c.chi_c, x.chi, x.r, c.phi_ff, h);
  } else {
    lateral_.idle_course();
  }
  phi_c = saturate(phi_c, -L.roll_max, L.roll_max);
  if (mode == Mode::flare) phi_c = saturate(phi_c, -land_.flare_roll_max, land_.flare_roll_max);
  if (shaped_handover) {
    phi_c = lateral_.roll_command_for(f_.handover_from.delta_a, x.phi, x.p);
    lateral_.initialise_shape(phi_c);
  } else if (init) {
    lateral_.initialise_shape(phi_c);
  } else {
    phi_c = lateral_.shape_roll(phi_c, h);
  }
  // Before rotation the gear holds the wings level. On the rollout the roll loop keeps its
  // integrator: in a crosswind it holds the aileron into the wind, as a pilot does.
  const bool before_rotation = mode == Mode::takeoff && !f_.rotated && x.Va < s_.rotation_Va;
  if (before_rotation && !init) lateral_.reset_roll_integrator();
  if (init) lateral_.initialise_roll(f_.handover_from.delta_a, phi_c, x.phi, x.p);
  const double delta_a = lateral_.roll(phi_c, x.phi, x.p, h);
  double delta_r = lateral_.yaw_damper(x.r, h);
  if (mode == Mode::manual_angle) delta_r -= st.yaw * L.max_r;
  return {phi_c, delta_a, delta_r};
}

// Longitudinal: the pitch command and throttle (flare and rollout, takeoff, held angles, or the
// speed and altitude law), the elevator; on the rollout also the rudder (delta_r) and the brakes.
Autopilot::LongitudinalOut Autopilot::longitudinal_step(Mode mode, const VehicleState& x, const Command& c, const Sticks& st, bool init,
                                                        double h, double& delta_r, double& brake) {
  const bool ovt = f_.override_theta;
  double theta_c = 0.0, delta_t = 0.0, delta_t_c = 0.0;
  if (mode == Mode::flare || mode == Mode::rollout) {
    const LandingLongitudinal l = landing_step(mode, x, c, h);
    theta_c = l.theta_c;
    delta_t = delta_t_c = l.delta_t;
    if (mode == Mode::rollout) delta_r = l.delta_r;
    brake = l.brake;
    law_.reset();
  } else if (mode == Mode::takeoff) {
    if (x.Va >= s_.rotation_Va) f_.rotated = true;
    theta_c = f_.rotated ? s_.takeoff_pitch : 0.0;
    delta_t = delta_t_c = s_.takeoff_throttle;
    law_.reset();
  } else if (mode == Mode::manual_angle) {
    theta_c = st.pitch * s_.angle_pitch_max;
    delta_t = delta_t_c = st.throttle;
    law_.reset();
  } else {
    if (init) {
      const double theta_needed =
          saturate(pitch_.pitch_command_for(f_.handover_from.delta_e, x.theta, x.q), law_.theta_min(), law_.theta_max());
      law_.initialise(x, c, theta_needed, f_.handover_from.delta_t);
    }
    const auto lo = law_.update(x, c, mode == Mode::climb, h);
    theta_c = ovt ? c.theta_c : lo.theta_c;
    delta_t = lo.delta_t;
    delta_t_c = lo.delta_t_c;
  }
  // On the ground before rotation the gear holds the attitude: no pitch or roll integration.
  const bool ground_roll = (mode == Mode::takeoff && !f_.rotated) || mode == Mode::rollout;
  if (ground_roll && !init) pitch_.reset();
  if (init) pitch_.initialise(f_.handover_from.delta_e, theta_c, x.theta, x.q);
  const double delta_e = pitch_.update(theta_c, x.theta, x.q, h);
  return {theta_c, delta_t, delta_t_c, delta_e};
}

// The height above the runway: the range finder's when it measures (centimetres), else the altitude
// estimate's above the touchdown point (a land item's h_td; without one, h_c), which drifts metres
// over a flight.
double Autopilot::runway_height(const VehicleState& x, const Command& c) {
  if (std::isfinite(x.h_agl)) return x.h_agl;
  return x.h - (c.landing ? c.h_td : c.h_c);
}

// Flare: the sink-rate flare's pitch, the throttle winding down to idle above the airspeed floor. Rollout: pitch 0, motor off, the rudder
// (nose wheel) on the course error to the runway's course (no land item: the course the
// rollout began on), brakes after rollout_brake_delay.
Autopilot::LandingLongitudinal Autopilot::landing_step(Mode mode, const VehicleState& x, const Command& c, double dt) {
  LandingLongitudinal l;
  if (mode == Mode::flare) {
    const double h = runway_height(x, c);
    l.theta_c = f_.flare.update(h, x.h_dot, dt, land_);
    const double Va_floor = std::isfinite(c.Va_c) ? land_.flare_airspeed_ratio * c.Va_c : 0.0;
    l.delta_t = f_.flare.throttle(h, x.Va, Va_floor, dt, land_);
    return l;
  }
  f_.rollout_time += dt;
  // positive rudder yaws the nose left (book sec. 4.2 signs): a course error to the right needs
  // negative rudder
  // the runway's course after a landing; after an aborted takeoff the course the rollout began on
  const double chi_err = tern::wrap_pi((c.landing ? c.chi_c : f_.rollout_chi) - x.chi);
  const auto& L = lateral_.gains();
  l.delta_r = saturate(-land_.rollout_steer_kp * chi_err, -L.max_r, L.max_r);
  l.brake = f_.rollout_time >= land_.rollout_brake_delay ? land_.rollout_brake : 0.0;
  return l;
}

}  // namespace tern::control
