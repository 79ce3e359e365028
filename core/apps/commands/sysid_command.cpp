// core/apps/commands/sysid_command.cpp: `tern sysid LOG --aircraft PRIOR --out DIR`: the uavbook's
// aerodynamic coefficients from a flight log (docs/system-identification.md): tern's estimator
// replays the log (attitude, wind, alpha, beta), then sysid/identify.hpp's regressions;
// sysid/sysid_output.hpp's files.
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "commands/commands.hpp"
#include "commands/estimator_replay.hpp"
#include "config/error.hpp"
#include "sysid/flight_data.hpp"
#include "sysid/command_delay.hpp"
#include "sysid/excitation_recovery.hpp"
#include "sysid/identify.hpp"
#include "sysid/identify_drag.hpp"
#include "sysid/instrumentation.hpp"
#include "sysid/motor_lag.hpp"
#include "sysid/prior_update.hpp"
#include "sysid/sysid_output.hpp"
#include "sysid/verdicts.hpp"

namespace tern::core {

namespace {

struct SysidOptionsCli {
  std::string log_dir, aircraft, out_dir, estimate, flow_angles = "accelerometer";
  std::vector<double> band = {sysid::SysidOptions{}.band_lo_hz, sysid::SysidOptions{}.band_hi_hz};
  double trim_window = sysid::SysidOptions{}.trim_window_s;
  double filter_hz = sysid::FlightSeriesOptions{}.filter_hz, rate_hz = sysid::FlightSeriesOptions{}.rate_hz;
  double oe_window = sysid::OutputErrorOptions{}.window_s;
  bool no_output_error = false;
  bool held_at_prior = false;
  bool accel_x_bias = false;
  bool keep_estimate = false;
  double gyro_cross_axis = sysid::SysidOptions{}.gyro_cross_axis;
  std::vector<double> command_delay_ms;  ///< empty: the prior's servos.delay_*; 1 value: every surface; 3: aileron, elevator, rudder
  std::optional<double> motor_tau_s;     ///< unset: estimated (sysid/motor_lag.hpp)
  std::vector<double> pitot_scale;       ///< empty: estimated; K, or K and its standard error (held)
  std::vector<std::string> sets;
};

/// The estimate: a given run, else tern's estimator over the log at log level sysid.
fs::path estimate_of(const SysidOptionsCli& o) {
  if (!o.estimate.empty()) return o.estimate;
  EstimatorReplay req;
  req.log_dir = o.log_dir;
  req.out_dir = (fs::path(o.out_dir) / "replay").string();
  req.sets = o.sets;
  req.level = LogLevel::sysid;
  req.quiet = true;
  req.kinematic = true;  // the estimate not shaped by any file's coefficients (estimator_replay.hpp)
  req.estimate_only = true;
  const FlightResult r = replay_estimator(req);
  return r.run_dir;
}

/// s, aileron, elevator, rudder: each command's delay after its stamp: --command-delay (held), else
/// the prior's servos.delay_a, _e, _r (where the estimate starts: sysid/command_delay.hpp).
std::array<double, 3> command_delays(const SysidOptionsCli& o, const Aircraft& prior) {
  if (o.command_delay_ms.empty()) return {prior.servo_delay_a, prior.servo_delay_e, prior.servo_delay_r};
  if (o.command_delay_ms.size() != 1 && o.command_delay_ms.size() != 3)
    throw ConfigError(fmt::format("--command-delay: {} values: expected one (every surface) or three (aileron elevator rudder), ms",
                                  o.command_delay_ms.size()));
  std::array<double, 3> d{};
  for (std::size_t i = 0; i < 3; ++i) {
    const double ms = o.command_delay_ms[o.command_delay_ms.size() == 1 ? 0 : i];
    if (!(std::abs(ms) <= 1000.0)) throw ConfigError(fmt::format("--command-delay: {} ms: expected -1000 .. 1000", ms));
    d[i] = 1e-3 * ms;
  }
  return d;
}

/// The thrust's lag behind the throttle: --motor-tau (held), else estimated from `series` (loaded
/// with the servos' lag), starting from the servos' (sysid/motor_lag.hpp).
sysid::MotorLag motor_lag(const SysidOptionsCli& o, const sysid::FlightTables& tables, const sysid::FlightSeries& series,
                          const Aircraft& prior, const sysid::SysidOptions& io) {
  if (o.motor_tau_s) {  // checked by identify_options
    return {
        {*o.motor_tau_s, 0.0, false, "given (--motor-tau)"}, {}, fmt::format("motor lag: {:.3f} s, given (--motor-tau)", *o.motor_tau_s)};
  }
  const auto throttle = [&](double tau) { return sysid::throttle_in_force(tables, series.t, tau); };
  return sysid::estimate_motor_lag(series, throttle, prior, io.airborne, prior.servo_tau);
}

/// The identification's options from the command line, each checked before the log is replayed
/// (a bad value is one error line, not one after the replay's seconds).
sysid::SysidOptions identify_options(const SysidOptionsCli& o) {
  if (o.band.size() != 2 || !(o.band[0] > 0.0) || !(o.band[1] > o.band[0]))
    throw ConfigError(fmt::format("--band: {} .. {} Hz: expected 0 < LO < HI", o.band.front(), o.band.back()));
  if (o.flow_angles != "accelerometer" && o.flow_angles != "estimator")
    throw ConfigError(fmt::format("--flow-angles: '{}': expected accelerometer or estimator", o.flow_angles));
  if (!(o.oe_window > 0.0)) throw ConfigError(fmt::format("--output-error-window: {} s: expected > 0", o.oe_window));
  if (o.motor_tau_s && !(*o.motor_tau_s >= 0.0 && *o.motor_tau_s <= 5.0))
    throw ConfigError(fmt::format("--motor-tau: {} s: expected 0 .. 5", *o.motor_tau_s));
  if (!(o.gyro_cross_axis >= 0.0 && o.gyro_cross_axis < 0.5))
    throw ConfigError(fmt::format("--gyro-cross-axis: {}: expected 0 <= value < 0.5 (rad/rad)", o.gyro_cross_axis));
  sysid::SysidOptions io;
  io.band_lo_hz = o.band[0], io.band_hi_hz = o.band[1], io.trim_window_s = o.trim_window;
  io.flow_angles = o.flow_angles == "estimator" ? sysid::FlowAngles::estimator : sysid::FlowAngles::accelerometer;
  io.output_error.enabled = !o.no_output_error, io.output_error.window_s = o.oe_window;
  io.scale_held_priors = !o.held_at_prior;
  io.fit_accel_x_bias = o.accel_x_bias;
  io.gyro_cross_axis = o.gyro_cross_axis;
  if (!o.pitot_scale.empty()) {
    io.pitot_scale = o.pitot_scale[0], io.pitot_scale_std_error = o.pitot_scale.size() > 1 ? o.pitot_scale[1] : 0.0;
    try {
      sysid::check_stated_pitot_scale(io.pitot_scale, io.pitot_scale_std_error);
    } catch (const std::invalid_argument& e) {
      throw ConfigError(fmt::format("--pitot-scale: {}", e.what()));
    }
  }
  return io;
}

int run_sysid(const SysidOptionsCli& o) {
  const Aircraft prior = load_aircraft(o.aircraft);
  const sysid::SysidOptions io = identify_options(o);
  const std::array<double, 3> delays = command_delays(o, prior);
  tables_from_mcap(o.log_dir);  // a run directory logged as MCAP only
  sysid::check_sensor_log(o.log_dir, o.estimate.empty());
  sysid::FlightTables tables = sysid::read_log_tables(o.log_dir);  // their units checked before the replay
  const ReplayScratch scratch(o.estimate.empty() ? fs::path(o.out_dir) / "replay" : fs::path(), o.keep_estimate);
  const fs::path estimate = estimate_of(o);
  sysid::FlightSeriesOptions so;
  so.servo_tau = prior.servo_tau, so.filter_hz = o.filter_hz, so.rate_hz = o.rate_hz;
  so.command_delay_s = delays;
  sysid::read_installation(estimate, so);
  sysid::DelayOptions timing;
  timing.estimate.fill(o.command_delay_ms.empty());  // --command-delay fixes them; else from the prior's, estimated
  sysid::read_estimate_table(tables, estimate);
  const auto load = [&](const std::array<double, 3>& delays) {
    sysid::FlightSeriesOptions with = so;
    with.command_delay_s = delays;
    sysid::FlightSeries series = sysid::series_from_tables(tables, with);
    sysid::recover_excitation(series);  // a log without topics/excitation.csv (excitation_recovery.hpp)
    return series;
  };
  const sysid::MotorLag motor = motor_lag(o, tables, load(delays), prior, io);
  so.motor_tau = motor.tau.estimate;
  sysid::SysidResult r = sysid::identify_timed(load, delays, prior, io, timing);
  r.motor_tau = motor.tau;
  r.notes.insert(r.notes.begin(), motor.line);
  sysid::apply_verdicts(r, prior, io);  // a moved held term (prior_update.hpp) rejected goes back to its moved value
  sysid::restore_prior(r);
  const std::string options = fmt::format(
      "band {}..{} Hz, trim windows {} s, flow angles from the {}, low-pass {} Hz, {} Hz samples, servo tau {} s, motor tau {} s, "
      "command delay "
      "{} ms, gyro cross-axis {}, {}, held terms {}",
      o.band[0], o.band[1], o.trim_window, o.flow_angles, o.filter_hz, o.rate_hz, prior.servo_tau, motor.tau.estimate,
      fmt::join(std::array<double, 3>{1e3 * r.command_delay_s[0], 1e3 * r.command_delay_s[1], 1e3 * r.command_delay_s[2]}, "/"),
      o.gyro_cross_axis, o.no_output_error ? "equation error only" : fmt::format("output error over {} s windows", o.oe_window),
      o.held_at_prior ? "at the prior (--held-at-prior)" : "scaled with their surface's identified derivative");
  const std::string estimate_text =
      o.estimate.empty() && !o.keep_estimate ? "tern's estimator replayed over the log (not kept: --keep-estimate)" : estimate.string();
  const sysid::SysidProvenance from{o.log_dir, o.aircraft, estimate_text, options};
  sysid::keep_loadable(r, from);
  sysid::drag_at_trim(r, prior);  // on the file as written: after the verdicts and keep_loadable
  sysid::write_sysid_outputs(r, from, o.out_dir);
  std::printf("%s", sysid::format_sysid_table(r).c_str());
  for (const auto& n : r.notes) std::printf("note: %s\n", n.c_str());
  std::printf("%s\n", sysid::identified_summary(r).c_str());
  std::printf("wrote %s/aircraft.yaml, sysid.json, index.html\n", o.out_dir.c_str());
  return 0;
}

}  // namespace

Command add_sysid_command(CLI::App& app) {
  auto o = std::make_shared<SysidOptionsCli>();
  auto* c = app.add_subcommand("sysid",
                               "identify the aircraft's aerodynamic coefficients from a flight log with actuators "
                               "(docs/system-identification.md)");
  c->add_option("log_dir", o->log_dir, "a sensor log with actuators (a tern flight log, or tern import's output)")
      ->required()
      ->check(CLI::ExistingDirectory);
  c->add_option("--aircraft", o->aircraft, "the prior aircraft file: mass, inertia, geometry, propulsion and the coefficients' priors")
      ->required()
      ->check(CLI::ExistingFile);
  c->add_option("--out", o->out_dir, "directory for aircraft.yaml, sysid.json and index.html")->required();
  c->add_option("--estimate", o->estimate, "a tern replay run of the log to take the estimate from (default: replay it now)")
      ->check(CLI::ExistingDirectory);
  c->add_option("--band", o->band, "LO HI: the frequency band of the moment regressions, Hz (default 0.1 4)")->expected(2);
  c->add_option("--trim-window", o->trim_window, "s: window of the trim regressions (lift, drag, bias terms; default 4)");
  c->add_option("--flow-angles", o->flow_angles,
                "accelerometer (alpha, beta from lift and side force; default) or estimator (the flight path's reconstruction against the "
                "steady wind)");
  c->add_option("--filter-hz", o->filter_hz, "Hz: the zero-phase low-pass every channel gets (default 10)");
  c->add_option("--rate", o->rate_hz, "Hz: samples after decimation (default 50)");
  c->add_option("--output-error-window", o->oe_window,
                "s: the output-error step restarts its simulated rates from the measured ones this often (default 5)");
  c->add_flag("--no-output-error", o->no_output_error, "equation error only (the rotational axes' output-error refinement skipped)");
  c->add_flag("--held-at-prior", o->held_at_prior,
              "terms the flight leaves undetermined keep the prior's values (default: C_L_q, C_L_delta_e, C_Y_delta_a, C_n_delta_a "
              "and C_ell_delta_r take their surface's identified-over-prior ratio, core/apps/sysid/prior_update.hpp)");
  c->add_flag("--accel-x-bias", o->accel_x_bias,
              "fit the accelerometer's x bias jointly with the drag polar (needs several airspeeds and a polar model that holds: "
              "docs/system-identification.md)");
  c->add_option("--gyro-cross-axis", o->gyro_cross_axis,
                "rad/rad: the largest share of one gyro axis's rate in another's (cross-axis sensitivity and mounting; default 0.02): "
                "widens the rolling and yawing moments' bounds, which cannot see it");
  c->add_option("--command-delay", o->command_delay_ms,
                "MS or A E R: each surface's command acts this long after its stamp (ms; one value for every surface, or aileron "
                "elevator rudder; negative: the log stamps it late), held; default: estimated from the flight by the output error, "
                "starting from the prior's servos.delay_a, _e, _r. A positive delay is written into aircraft.yaml's servos "
                "(docs/system-identification.md)")
      ->expected(1, 3);
  c->add_option("--motor-tau", o->motor_tau_s,
                "S: the thrust's first-order lag behind the throttle's command (the motor and propeller spinning up), held; default: "
                "estimated from the x force (docs/system-identification.md)");
  c->add_option("--pitot-scale", o->pitot_scale,
                "K [SE]: the true airspeed over the pitot's, measured (a calibration), and its standard error (default 0), held; "
                "default: estimated from the wind triangle where the flight turns (docs/system-identification.md)")
      ->expected(1, 2);
  c->add_flag("--keep-estimate", o->keep_estimate,
              "keep the estimator's replay of the log in DIR/replay (the state at every message: hundreds of MB for a long flight; "
              "--estimate DIR/replay/<run> takes it next time)");
  c->add_option("--set", o->sets, "INSTANCE.PARAM=VALUE: an estimator parameter for the replay, as tern replay --set")
      ->type_name("INSTANCE.PARAM=VALUE");
  return {c, [o] { return run_sysid(*o); }};
}

}  // namespace tern::core
