// signal_generator adapter. See signal_generator_plugin.hpp and tern/signal_generator/signal.hpp.
#include "signal_generator_plugin.hpp"

#include <spdlog/spdlog.h>

namespace tern::signal {

void SignalGeneratorPlugin::configure() {
  declare(follower_, "follower_command", "the path follower's command (remap its controller_command here)");
  declare(phase_, "flight_phase", "flight phase: start_phase cruise waits for the first cruise", Need::optional);
  declare(internals_, "controller_internals", "the controller's phi_c, theta_c: base of roll and pitch signals", Need::optional);
  declare(command_, "controller_command", "the follower's command with the chosen loop's command replaced");
  declare(loop_, "loop", "roll",
          ParamSpec("", 0, 0, "loop whose command is replaced: roll phi_c, pitch theta_c, course chi_c, altitude h_c, airspeed Va_c")
              .one_of({"roll", "pitch", "course", "altitude", "airspeed"})
              .start_only());
  declare(waveform_, "waveform", "square",
          ParamSpec("", 0, 0, "signal shape (signal.hpp)").one_of({"step", "square", "sine", "triangle", "sawtooth", "doublet"}));
  declare(amplitude_, "amplitude", 0.1,
          ParamSpec("rad, m or m/s", -100.0, 100.0, "signal height: command = base + offset + amplitude * w(t) (the loop's unit)"));
  declare(period_, "period", 4.0, ParamSpec("s", 0.1, 3600.0, "signal period; step, square, doublet: first edge at period/2"));
  declare(offset_, "offset", 0.0, ParamSpec("rad, m or m/s", -1000.0, 1000.0, "added to the base (the loop's unit)"));
  declare(
      reference_, "reference", "command",
      ParamSpec("", 0, 0, "base: command = the loop's command at engagement; absolute = 0").one_of({"command", "absolute"}).start_only());
  declare(start_time_, "start_time", 20.0, ParamSpec("s", 0.0, 1e6, "engagement, after the start of start_phase").start_only());
  declare(start_phase_, "start_phase", "cruise",
          ParamSpec("", 0, 0, "start_time counts from: flight = t 0, cruise = the first cruise phase")
              .one_of({"flight", "cruise"})
              .start_only());
  loop_value_ = *loop_from_name(loop_());
  reference_value_ = *reference_from_name(reference_());
}

double SignalGeneratorPlugin::latched_base(const msg::ControllerCommand& f) const {
  if (reference_value_ == Reference::absolute) return 0.0;
  switch (loop_value_) {
    case Loop::roll: return internals_.has_value() ? internals_->phi_c : 0.0;
    case Loop::pitch: return internals_.has_value() ? internals_->theta_c : 0.0;
    case Loop::course: return f.chi_c;
    case Loop::altitude: return f.h_c;
    case Loop::airspeed: return f.Va_c;
  }
  return 0.0;
}

void SignalGeneratorPlugin::try_engage(Nanos now, const msg::ControllerCommand& f) {
  if (!flight_.anchor) {
    if (start_phase_() == "flight")
      flight_.anchor = 0;
    else if (phase_.has_value() && phase_->phase == msg::Phase::cruise)
      flight_.anchor = phase_->since;
  }
  if (!flight_.anchor || now < *flight_.anchor + from_seconds(start_time_())) return;
  flight_.engaged = now;
  flight_.base = latched_base(f);
  if ((loop_value_ == Loop::roll || loop_value_ == Loop::pitch) && reference_value_ == Reference::command && !internals_.has_value())
    log().warn("no controller_internals: the {} signal's base is 0", loop_name(loop_value_));
  log().info("{} signal on {} engaged at t={:.3f} s, base {:.4f} {}", waveform_(), command_symbol(loop_value_), to_seconds(now),
             flight_.base, loop_unit(loop_value_));
}

void SignalGeneratorPlugin::step(Nanos now) {
  if (!follower_.has_value()) return;
  msg::ControllerCommand out = *follower_;
  out.stamp = now;
  if (!flight_.engaged) try_engage(now, out);
  if (flight_.engaged) {
    const double t = to_seconds(now - *flight_.engaged);
    const double v = flight_.base + offset_() + amplitude_() * waveform(*waveform_from_name(waveform_()), t, period_());
    switch (loop_value_) {
      case Loop::roll:
        out.phi_c = v;
        out.override_phi = true;
        break;
      case Loop::pitch:
        out.theta_c = v;
        out.override_theta = true;
        break;
      case Loop::course: out.chi_c = v; break;
      case Loop::altitude: out.h_c = v; break;
      case Loop::airspeed: out.Va_c = v; break;
    }
  }
  command_.publish(out);
}

std::vector<std::pair<std::string, double>> SignalGeneratorPlugin::summary() const {
  if (!flight_.engaged) return {{"engaged_s", -1.0}};
  return {{"engaged_s", to_seconds(*flight_.engaged)}, {"base", flight_.base}};
}

}  // namespace tern::signal
