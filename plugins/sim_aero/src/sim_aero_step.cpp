// SimAero: a step of the world: the aircraft integrated, the sensors published when due, the
// truth, the ground impact and the flight's summary (see sim_aero_plugin.hpp).
#include "sim_aero_plugin.hpp"

namespace tern::sim_aero {

void SimAero::step(Nanos now) {
  if (!f_.sim) initialise();
  sim::Deltas cmd = f_.default_cmd;
  if (actuators_in_.has_value()) {
    const msg::Actuators& a = actuators_in_.get();
    cmd.delta_a = a.delta_a;
    cmd.delta_e = a.delta_e;
    cmd.delta_r = a.delta_r;
    cmd.delta_t = a.delta_t;
    cmd.brake = a.brake;
  }
  f_.sim->set_command(cmd);  // throws on NaN: an error, not a NaN flight
  apply_live_params();
  if (!f_.stepped) {
    publish_due(f_.t);
    f_.stepped = true;
  }
  while (f_.t < now) {
    const Nanos dt = std::min(f_.sim_dt, now - f_.t);
    f_.sim->step(static_cast<double>(dt) * 1e-9);
    f_.t += dt;
    ++f_.steps;
    publish_due(f_.t);
  }
  if (f_.sim->crashed() && !f_.crash_reported) report_crash();
}

std::vector<std::pair<std::string, double>> SimAero::summary() const {
  std::vector<std::pair<std::string, double>> s = {{"sim_steps", static_cast<double>(f_.steps)},
                                                   {"sim_crashed", f_.sim && f_.sim->crashed() ? 1.0 : 0.0}};
  if (f_.sensors) {
    // what the installation and the sky did to the sensors (sim::SensorEffects)
    const sim::SensorEffects& e = f_.sensors->effects();
    s.insert(s.end(), {{"gnss_fixes", e.gnss_fixes},
                       {"gnss_fixes_degraded", e.gnss_degraded},
                       {"gnss_fixes_lost", e.gnss_lost},
                       {"gnss_velocity_lag_max_mps", e.gnss_velocity_lag_max},
                       {"baro_static_error_max_pa", e.baro_static_error_max}});
  }
  if (f_.sim && f_.sim->crashed()) {
    const ImpactFacts m = impact();
    s.insert(s.end(), {{"impact_t_s", m.t},
                       {"impact_p_n_m", m.p_ned.x()},
                       {"impact_p_e_m", m.p_ned.y()},
                       {"impact_ground_speed_mps", m.v_ned.head<2>().norm()},
                       {"impact_sink_rate_mps", m.v_ned.z()},
                       {"impact_airspeed_mps", m.Va},
                       {"impact_roll_deg", m.phi * 180.0 / tern::kPi},
                       {"impact_pitch_deg", m.theta * 180.0 / tern::kPi}});
    // what struck (end_detail names it): the gear's hard point or wheel, 1-based (0: none,
    // the CG), and how fast that point moved
    const auto& im = f_.sim->impact();
    s.insert(s.end(), {{"impact_hard_point", static_cast<double>(im.hard_point + 1)},
                       {"impact_wheel", static_cast<double>(im.wheel + 1)},
                       {"impact_point_speed_mps", im.point_speed},
                       {"impact_point_sink_mps", im.point_sink}});
  }
  return s;
}

SimAero::ImpactFacts SimAero::impact() const {
  const auto& m = f_.sim->impact();
  const Eigen::Quaterniond q = sim::attitude(m.x);
  const Eigen::Vector3d eul = tern::euler_from_quaternion(q);
  return {m.t, m.x.segment<3>(sim::PN), q * m.x.segment<3>(sim::U), m.Va, eul.x(), eul.y()};
}

void SimAero::report_crash() {
  f_.crash_reported = true;
  const ImpactFacts m = impact();
  const std::string detail = fmt::format(
      "the aircraft hit the ground ({}) at t = {:.3f} s at p_n {:.1f} m, p_e {:.1f} m: ground speed {:.1f} m/s, sink rate {:.1f} m/s, "
      "airspeed {:.1f} m/s, roll {:.0f} deg, pitch {:.0f} deg",
      f_.sim->impact().what, m.t, m.p_ned.x(), m.p_ned.y(), m.v_ned.head<2>().norm(), m.v_ned.z(), m.Va, m.phi * 180.0 / tern::kPi,
      m.theta * 180.0 / tern::kPi);
  log().warn("{}", detail);
  context().end_flight("crash", detail);
}

void SimAero::apply_live_params() {
  f_.sim->set_steady_wind(Eigen::Vector3d(wind_()[0], wind_()[1], wind_()[2]));
  if (turbulence_() != f_.turbulence_applied) {
    f_.sim->set_turbulence(sim::dryden_preset(turbulence_()));
    f_.turbulence_applied = turbulence_();
  }
}

void SimAero::publish_due(Nanos t) {
  using Poll = sim::SensorSchedule::Poll;
  std::optional<sim::Truth> truth;
  auto get_truth = [&]() -> const sim::Truth& {
    if (!truth) {
      truth.emplace();
      truth->x = f_.sim->state();
      if (f_.sensors->params().imu_position.isZero()) {
        truth->fm = f_.sim->evaluate();
      } else {  // the lever arm needs the angular acceleration: one evaluation gives both
        truth->omega_dot = sim::derivative(f_.sim->aircraft(), truth->x, f_.sim->surfaces(), f_.sim->wind(), &truth->fm).segment<3>(sim::P);
      }
      truth->mass = f_.sim->aircraft().mass;
      truth->rho = f_.sim->aircraft().rho;
      truth->throttle = f_.sim->surfaces().delta_t;
    }
    return *truth;
  };
  auto run = [&](SensorSlot& s, auto&& sample) {
    const Poll p = s.schedule.poll(t);
    if (p == Poll::idle) return;
    sample(p == Poll::sample);
  };
  run(imu_, [&](bool ok) {
    if (!ok) return;
    const auto m = f_.sensors->imu(get_truth(), imu_.schedule.dt_since_last(t));
    imu_.schedule.last_sample = t;
    msg::Imu out;
    out.stamp = t;
    out.accel = m.accel;
    out.gyro = m.gyro;
    out.temperature = m.temperature;
    if (imu_.non_finite(t)) out.accel = out.gyro = Eigen::Vector3d::Constant(kNaN);
    imu_out_.publish(out);
  });
  run(mag_, [&](bool ok) {
    if (!ok) return;
    const auto m = f_.sensors->mag(get_truth(), mag_.schedule.dt_since_last(t));
    mag_.schedule.last_sample = t;
    msg::Mag out;
    out.stamp = t;
    out.field = mag_.non_finite(t) ? Eigen::Vector3d::Constant(kNaN) : m.field;
    mag_out_.publish(out);
  });
  run(baro_, [&](bool ok) {
    if (!ok) return;
    const auto m = f_.sensors->baro(get_truth(), baro_.schedule.dt_since_last(t));
    baro_.schedule.last_sample = t;
    msg::Baro out;
    out.stamp = t;
    out.pressure = baro_.non_finite(t) ? kNaN : m.pressure;
    out.temperature = m.temperature;
    baro_out_.publish(out);
  });
  run(range_, [&](bool ok) {
    if (!ok) return;
    range_.schedule.last_sample = t;
    msg::Range out;
    out.stamp = t;
    out.distance = range_.non_finite(t) ? kNaN : f_.rangefinder->distance(get_truth().x);
    out.min_range = f_.sensors->params().range_min;
    out.max_range = f_.sensors->params().range_max;
    range_out_.publish(out);
  });
  run(diff_, [&](bool ok) {
    if (!ok) return;
    const double dt = diff_.schedule.dt_since_last(t);
    const auto m = t < tern::from_seconds(pitot_cover_()) ? f_.sensors->diff_pressure(covered_pitot(get_truth()), dt)
                                                          : f_.sensors->diff_pressure(get_truth(), dt);
    diff_.schedule.last_sample = t;
    msg::DiffPressure out;
    out.stamp = t;
    out.pressure = diff_.non_finite(t) ? kNaN : m.pressure;
    out.temperature = m.temperature;
    diff_out_.publish(out);
  });
  run(gnss_, [&](bool ok) {
    msg::Gnss out;
    out.stamp = out.time_of_validity = t;
    if (ok) {
      out = sim::gnss_message(f_.sensors->gnss(get_truth(), gnss_.schedule.dt_since_last(t)), t);
      gnss_.schedule.last_sample = t;
      if (gnss_.non_finite(t)) out.lat = out.lon = out.alt = kNaN;
    } else if (!gnss_.schedule.enabled) {
      return;  // switched off: silent
    }
    // In a drop-out window the receiver still reports, without a fix. Every report leaves
    // the receiver gnss_latency after its time of validity.
    out.stamp = t + f_.gnss_latency;
    f_.gnss_pending.push_back(out);
  });
  while (!f_.gnss_pending.empty() && f_.gnss_pending.front().stamp <= t) {
    gnss_out_.publish(f_.gnss_pending.front());
    f_.gnss_pending.pop_front();
  }
  if (f_.truth_sched.poll(t) == Poll::sample) publish_truth(t, get_truth());
  if (f_.rc_sched.poll(t) == Poll::sample) {
    msg::Rc rc = pilot_in_.has_value() ? *pilot_in_ : msg::Rc{};
    rc.stamp = t;
    rc_out_.publish(rc);
  }
  if (f_.status_sched.poll(t) == Poll::sample) {
    msg::FcuStatus st;
    st.stamp = t;
    st.armed = armed_() && boot_calibrated(t);
    st.offboard = offboard_();
    const auto& ac = f_.sim->aircraft();
    const double V_in = ac.prop.V_max * f_.sim->surfaces().delta_t;
    st.battery_voltage = ac.prop.V_max;
    st.battery_current = std::max(0.0, (V_in - ac.prop.K_Q * get_truth().fm.prop.Omega) / ac.prop.R_motor);
    status_out_.publish(st);
  }
}

bool SimAero::boot_calibrated(Nanos t) {
  const sim::BootCalibration* cal = f_.sensors->boot_calibration();
  if (cal == nullptr) return true;
  if (!cal->gyro_done() || (diff_.enabled() && !cal->diff().done) || (baro_.enabled() && !cal->baro_ground().done)) return false;
  if (!f_.boot_reported) {
    f_.boot_reported = true;
    const Eigen::Vector3d b = cal->gyro_bias();
    log().info(
        "t={:.3f} s: FCU boot calibration done: gyro bias [{:.5f}, {:.5f}, {:.5f}] rad/s, pitot zero {:.2f} Pa, "
        "ground pressure {:.1f} Pa ({} restarts for movement)",
        tern::to_seconds(t), b.x(), b.y(), b.z(), cal->diff().offset, cal->baro_ground().offset,
        cal->gyro_restarts() + cal->diff().restarts + cal->baro_ground().restarts);
    // The world knows what the FCU cannot: whether the aircraft sat still while it averaged.
    const double off = (b - f_.sensors->gyro_bias()).norm();
    if (off > kMovedDuringCalibration)
      log().warn(
          "the aircraft moved during the FCU's gyro calibration: the bias it removes is {:.2f} deg/s off "
          "(weathervaning in the wind? point it into the wind, as for a takeoff)",
          off * 180.0 / tern::kPi);
  }
  return true;
}

sim::Truth SimAero::covered_pitot(sim::Truth t) {
  t.fm.air.v_air.setZero();
  t.fm.air.Va = 0.0;
  return t;
}

void SimAero::publish_truth(Nanos t, const sim::Truth& tr) {
  const sim::StateVector& x = tr.x;
  msg::State s;
  s.stamp = t;
  s.p_n = x[sim::PN];
  s.p_e = x[sim::PE];
  s.p_d = x[sim::PD];
  s.u = x[sim::U];
  s.v = x[sim::V];
  s.w = x[sim::W];
  const Eigen::Quaterniond q = sim::attitude(x);
  const Eigen::Vector3d v_ned = q * Eigen::Vector3d(x[sim::U], x[sim::V], x[sim::W]);
  s.v_n = v_ned.x();
  s.v_e = v_ned.y();
  s.v_d = v_ned.z();
  const Eigen::Vector3d eul = tern::euler_from_quaternion(q);
  s.phi = eul.x();
  s.theta = eul.y();
  s.psi = eul.z();
  s.quat = q;
  s.p = x[sim::P];
  s.q = x[sim::Q];
  s.r = x[sim::R];
  s.Va = tr.fm.air.Va;
  s.alpha = tr.fm.air.alpha;
  s.beta = tr.fm.air.beta;
  s.Vg = v_ned.norm();
  s.chi = tern::wrap_pi(std::atan2(v_ned.y(), v_ned.x()));
  s.gamma = s.Vg > 1e-6 ? std::asin(std::clamp(-v_ned.z() / s.Vg, -1.0, 1.0)) : 0.0;
  const Eigen::Vector3d w = f_.sim->wind_ned();
  s.w_n = w.x();
  s.w_e = w.y();
  s.w_d = w.z();
  s.b_x = f_.sensors->gyro_bias().x();
  s.b_y = f_.sensors->gyro_bias().y();
  s.b_z = f_.sensors->gyro_bias().z();
  s.origin_lat = f_.sensors->params().origin_lat;
  s.origin_lon = f_.sensors->params().origin_lon;
  s.origin_alt = f_.sensors->params().origin_alt;
  s.origin_valid = true;
  s.valid = true;
  truth_out_.publish(s);
}

}  // namespace tern::sim_aero
