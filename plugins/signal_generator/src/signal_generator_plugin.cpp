// signal_generator adapter. See signal_generator_plugin.hpp and tern/signal_generator/signal.hpp.
#include "signal_generator_plugin.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "tern/aircraft.hpp"

namespace tern::signal {

namespace {

constexpr std::array<std::string_view, 4> kSurfaceNames{"delta_a", "delta_e", "delta_r", "delta_t"};

std::optional<Surface> surface_from_name(std::string_view n) {
  for (std::size_t i = 0; i < kSurfaceNames.size(); ++i)
    if (kSurfaceNames[i] == n) return static_cast<Surface>(i);
  return std::nullopt;
}

std::optional<Shape> shape_from_name(std::string_view n) {
  if (n == "chirp") return Shape::chirp;
  if (n == "multisine") return Shape::multisine;
  if (n == "3211") return Shape::input_3211;
  if (n == "doublet") return Shape::doublet;
  return std::nullopt;
}

std::string_view shape_name(Shape s) {
  switch (s) {
    case Shape::chirp: return "chirp";
    case Shape::multisine: return "multisine";
    case Shape::input_3211: return "3211";
    case Shape::doublet: return "doublet";
  }
  return "chirp";
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, sep)) out.push_back(trim(item));
  return out;
}

/// The i-th of a per-manoeuvre list (one value: every manoeuvre).
double pick(const std::vector<double>& v, std::size_t i) { return v.size() == 1 ? v[0] : v[i]; }

}  // namespace

double Manoeuvre::duration() const {
  switch (shape) {
    case Shape::chirp:
    case Shape::multisine: return chirp.t_rec;
    case Shape::input_3211: return 7.0 * pulse_width;
    case Shape::doublet: return 2.0 * pulse_width;
  }
  return 0.0;
}

std::array<double, 4> Manoeuvre::excitation(double t) const {
  std::array<double, 4> e{};
  for (std::size_t j = 0; j < axes.size(); ++j) {
    double w = 0.0;
    switch (shape) {
      case Shape::chirp: w = chirp.value(t); break;
      case Shape::multisine: w = multisine[j].value(t); break;
      case Shape::input_3211: w = input_3211(t, pulse_width); break;
      case Shape::doublet: w = input_doublet(t, pulse_width); break;
    }
    e[static_cast<std::size_t>(axes[j])] += magnitude[j] * w;
  }
  return e;
}

std::string Manoeuvre::describe() const {
  std::string axes_text;
  for (std::size_t j = 0; j < axes.size(); ++j) {
    if (j > 0) axes_text += "+";
    axes_text += kSurfaceNames[static_cast<std::size_t>(axes[j])];
  }
  std::string mags;
  for (std::size_t j = 0; j < magnitude.size(); ++j) mags += fmt::format("{}{:.4g}", j > 0 ? "/" : "", magnitude[j]);
  if (shape == Shape::chirp || shape == Shape::multisine)
    return fmt::format("{} {} {:.3g}..{:.3g} Hz over {:.4g} s, magnitude {}", axes_text, shape_name(shape), chirp.f_start_hz,
                       chirp.f_stop_hz, chirp.t_rec, mags);
  return fmt::format("{} {} T_p {:.4g} s, magnitude {}", axes_text, shape_name(shape), pulse_width, mags);
}

// ---- configuration --------------------------------------------------------------------------

void SignalGeneratorPlugin::configure() {
  declare(
      loop_, "loop", "roll",
      ParamSpec(
          "", 0, 0,
          "loop mode (axis empty): loop whose command is replaced: roll phi_c, pitch theta_c, course chi_c, altitude h_c, airspeed Va_c")
          .one_of({"roll", "pitch", "course", "altitude", "airspeed"})
          .start_only());
  declare(axis_, "axis", "",
          ParamSpec("", 0, 0,
                    "surface mode: the manoeuvre list, comma-separated, each delta_a, delta_e, delta_r, delta_t or several joined by + "
                    "(at once: multisine); empty: loop mode on `loop` (ArduPilot's SID_AXIS)")
              .start_only());
  declare(start_time_, "start_time", 20.0, ParamSpec("s", 0.0, 1e6, "engagement, after the start of start_phase").start_only());
  declare(start_phase_, "start_phase", "cruise",
          ParamSpec("", 0, 0, "start_time counts from: flight = t 0, cruise = the first cruise phase")
              .one_of({"flight", "cruise"})
              .start_only());
  if (trim(axis_()).empty())
    configure_loop_mode();
  else
    configure_surface_mode();
}

void SignalGeneratorPlugin::configure_loop_mode() {
  surface_mode_ = false;
  declare(follower_, "follower_command", "the path follower's command (remap its controller_command here)");
  declare(phase_, "flight_phase", "flight phase: start_phase cruise waits for the first cruise", Need::optional);
  declare(internals_, "controller_internals", "the controller's phi_c, theta_c: base of roll and pitch signals", Need::optional);
  declare(command_, "controller_command", "the follower's command with the chosen loop's command replaced");
  declare(waveform_, "waveform", "square",
          ParamSpec("", 0, 0, "signal shape (signal.hpp)").one_of({"step", "square", "sine", "triangle", "sawtooth", "doublet"}));
  declare(amplitude_, "amplitude", 0.1,
          ParamSpec("rad, m or m/s", -100.0, 100.0, "signal height: command = base + offset + amplitude * w(t) (the loop's unit)"));
  declare(period_, "period", 4.0, ParamSpec("s", 0.1, 3600.0, "signal period; step, square, doublet: first edge at period/2"));
  declare(offset_, "offset", 0.0, ParamSpec("rad, m or m/s", -1000.0, 1000.0, "added to the base (the loop's unit)"));
  declare(
      reference_, "reference", "command",
      ParamSpec("", 0, 0, "base: command = the loop's command at engagement; absolute = 0").one_of({"command", "absolute"}).start_only());
  loop_value_ = *loop_from_name(loop_());
  reference_value_ = *reference_from_name(reference_());
}

void SignalGeneratorPlugin::configure_surface_mode() {
  surface_mode_ = true;
  declare(controller_actuators_, "controller_actuators", "the controller's command (remap its actuators output here)");
  declare(state_, "state", "the estimate: the envelope and the airspeed sequence");
  declare(phase_, "flight_phase", "flight phase: start_phase cruise waits for the first cruise; a change aborts", Need::optional);
  declare(rc_, "rc", "RC receiver: rc_channel's switch engages and aborts; failsafe or override aborts", Need::optional);
  declare(mission_edit_, "mission_edit", "a mission edit (a failsafe's, an operator's) aborts", Need::optional);
  declare(actuators_, "actuators", "the controller's command with the excitation added, clamped to the surfaces' limits");
  declare(excitation_, "excitation", "the increments added this step (rad; delta_t: throttle fraction); 0 outside a manoeuvre");
  declare(waveform_, "waveform", "chirp",
          ParamSpec("", 0, 0, "chirp, multisine, 3211 or doublet: one name, or one per manoeuvre, comma-separated (signal.hpp)"));
  declare(magnitude_, "magnitude", std::vector<double>{0.0349},
          ParamSpec("rad; delta_t: 0..1", -1.0, 1.0,
                    "peak excitation per axis named in `axis`, in order (one value: every axis) (ArduPilot's SID_MAGNITUDE)"));
  declare(f_start_hz_, "f_start_hz", std::vector<double>{0.2},
          ParamSpec("Hz", 0.001, 50.0, "chirp, multisine: lowest frequency, one value or one per manoeuvre (SID_F_START_HZ)"));
  declare(f_stop_hz_, "f_stop_hz", std::vector<double>{2.0},
          ParamSpec("Hz", 0.001, 50.0, "chirp, multisine: highest frequency, one value or one per manoeuvre (SID_F_STOP_HZ)"));
  declare(t_rec_, "t_rec", std::vector<double>{20.0},
          ParamSpec("s", 0.1, 600.0, "chirp, multisine: record length, fades included, one value or one per manoeuvre (SID_T_REC)"));
  declare(t_fade_in_, "t_fade_in", 2.0, ParamSpec("s", 0.0, 600.0, "chirp: half-cosine rise at its start, inside t_rec (SID_T_FADE_IN)"));
  declare(t_fade_out_, "t_fade_out", 1.0, ParamSpec("s", 0.0, 600.0, "chirp: half-cosine fall at its end, inside t_rec (SID_T_FADE_OUT)"));
  declare(pulse_width_, "pulse_width", std::vector<double>{0.5},
          ParamSpec("s", 0.01, 60.0, "3211, doublet: the unit pulse T_p, one value or one per manoeuvre"));
  declare(t_gap_, "t_gap", 4.0, ParamSpec("s", 0.0, 600.0, "pass-through between two manoeuvres (the aircraft settles)"));
  declare(Va_sequence_, "Va_sequence", std::vector<double>{},
          ParamSpec("m/s", 1.0, 200.0,
                    "mission: fly the list once at each airspeed, in order, when the estimate holds it (empty: once, at start_time)")
              .start_only());
  declare(Va_tolerance_, "Va_tolerance", 1.0, ParamSpec("m/s", 0.1, 20.0, "steady: |Va - Va_sequence[i]| below this"));
  declare(t_settle_, "t_settle", 5.0, ParamSpec("s", 0.0, 600.0, "steady: for this long, wings level (|phi| < phi_settle)"));
  declare(phi_settle_, "phi_settle", 0.1, ParamSpec("rad", 0.0, 1.5, "steady: |phi| below this"));
  declare(engage_, "engage", "mission",
          ParamSpec("", 0, 0, "mission: automatic (start_time, Va_sequence); now: fly the list once now; off: abort, pass through")
              .one_of({"mission", "now", "off"}));
  declare(rc_channel_, "rc_channel", std::int64_t{-1},
          ParamSpec("", -1, 3, "RC aux channel of the engage switch: above 0.5 flies the list once, below aborts (-1: none)"));
  declare(phi_max_, "phi_max", 0.7, ParamSpec("rad", 0.01, 1.6, "envelope: |phi| above this aborts"));
  declare(theta_max_, "theta_max", 0.5, ParamSpec("rad", 0.01, 1.6, "envelope: |theta| above this aborts"));
  declare(Va_min_, "Va_min", 0.0, ParamSpec("m/s", 0.0, 200.0, "envelope: Va below this aborts (0: no floor)"));
  declare(h_min_, "h_min", 0.0, ParamSpec("m", -1e4, 1e5, "envelope: altitude above the origin below this aborts"));

  const std::filesystem::path f = context().aircraft_file();
  const tern::Aircraft ac = f.empty() ? tern::Aircraft{} : tern::load_aircraft(f.string());
  max_delta_ = {ac.max_delta_a, ac.max_delta_e, ac.max_delta_r};
  (void)plan();  // refuses a bad list now, with the parameter's name
}

std::vector<Manoeuvre> SignalGeneratorPlugin::plan() const {
  const auto bad = [&](const char* p, const std::string& value, const std::string& why) {
    return ParamError(fmt::format("parameter '{}': {}: {}", qname(p), value, why));
  };
  const auto list_text = [](const std::vector<double>& v) {
    std::string s = "[";
    for (std::size_t i = 0; i < v.size(); ++i) s += fmt::format("{}{}", i > 0 ? ", " : "", v[i]);
    return s + "]";
  };
  std::vector<Manoeuvre> out;
  const auto groups = split(axis_(), ',');
  for (const auto& g : groups)  // the names first: a wrong one explains a wrong count below
    for (const auto& name : split(g, '+'))
      if (!surface_from_name(name))
        throw bad("axis", "\"" + name + "\"",
                  loop_from_name(name) ? "a loop: loops are excited in loop mode (axis empty, loop: " + name + ")"
                                       : "not a surface (delta_a, delta_e, delta_r, delta_t)");
  const auto shapes = split(waveform_(), ',');
  if (shapes.size() != 1 && shapes.size() != groups.size())
    throw bad("waveform", waveform_(), fmt::format("give one waveform or one per manoeuvre ({})", groups.size()));
  for (const char* p : {"f_start_hz", "f_stop_hz", "t_rec", "pulse_width"}) {
    const auto& v = std::string_view(p) == "f_start_hz"  ? f_start_hz_()
                    : std::string_view(p) == "f_stop_hz" ? f_stop_hz_()
                    : std::string_view(p) == "t_rec"     ? t_rec_()
                                                         : pulse_width_();
    if (v.size() != 1 && v.size() != groups.size())
      throw bad(p, list_text(v), fmt::format("give one value or one per manoeuvre ({})", groups.size()));
  }
  std::size_t n_axes = 0;
  for (const auto& g : groups) n_axes += split(g, '+').size();
  if (magnitude_().size() != 1 && magnitude_().size() != n_axes)
    throw bad("magnitude", list_text(magnitude_()), fmt::format("give one value or one per axis named in axis ({})", n_axes));
  std::size_t axis_index = 0;
  for (std::size_t i = 0; i < groups.size(); ++i) {
    Manoeuvre m;
    for (const auto& name : split(groups[i], '+')) {
      const auto s = surface_from_name(name);
      if (std::find(m.axes.begin(), m.axes.end(), *s) != m.axes.end()) throw bad("axis", "\"" + groups[i] + "\"", "names a surface twice");
      m.axes.push_back(*s);
      const double mag = magnitude_().size() == 1 ? magnitude_()[0] : magnitude_()[axis_index];
      if (*s == Surface::delta_t && std::abs(mag) > 1.0) throw bad("magnitude", fmt::format("{}", mag), "throttle beyond 1");
      m.magnitude.push_back(mag);
      ++axis_index;
    }
    const std::string& shape_text = shapes.size() == 1 ? shapes[0] : shapes[i];
    const auto shape = shape_from_name(shape_text);
    if (!shape) throw bad("waveform", "\"" + shape_text + "\"", "not a surface-mode waveform (chirp, multisine, 3211, doublet)");
    m.shape = *shape;
    if (m.axes.size() > 1 && m.shape != Shape::multisine)
      throw bad("axis", "\"" + groups[i] + "\"", "several surfaces at once need waveform multisine (orthogonal harmonics)");
    m.chirp = Chirp{pick(f_start_hz_(), i), pick(f_stop_hz_(), i), pick(t_rec_(), i), m.shape == Shape::chirp ? t_fade_in_() : 0.0,
                    m.shape == Shape::chirp ? t_fade_out_() : 0.0};
    m.pulse_width = pick(pulse_width_(), i);
    try {
      if (m.shape == Shape::chirp) m.chirp.validate();
      if (m.shape == Shape::multisine)
        for (std::size_t j = 0; j < m.axes.size(); ++j)
          m.multisine.emplace_back(m.chirp.f_start_hz, m.chirp.f_stop_hz, m.chirp.t_rec, static_cast<int>(m.axes.size()),
                                   static_cast<int>(j));
    } catch (const std::invalid_argument& e) {
      // signal.hpp's messages begin with the parameter at fault ("f_stop_hz 1 must be above ...").
      const std::string what = e.what();
      throw ParamError(
          fmt::format("parameter '{}': manoeuvre {} ({} {}): {}", qname(what.substr(0, what.find(' '))), i, groups[i], shape_text, what));
    }
    out.push_back(std::move(m));
  }
  return out;
}

// ---- loop mode ------------------------------------------------------------------------------

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
  if (surface_mode_)
    step_surfaces(now);
  else
    step_loop(now);
}

void SignalGeneratorPlugin::step_loop(Nanos now) {
  if (!follower_.has_value()) return;
  msg::ControllerCommand out = *follower_;
  out.stamp = now;
  if (!flight_.engaged) try_engage(now, out);
  if (flight_.engaged) {
    const double t = to_seconds(now - *flight_.engaged);
    const auto w = waveform_from_name(waveform_());
    const double v = flight_.base + offset_() + amplitude_() * (w ? waveform(*w, t, period_()) : 0.0);
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

// ---- surface mode ---------------------------------------------------------------------------

std::optional<std::string> SignalGeneratorPlugin::envelope_violation() const {
  if (!state_.has_value() || !state_->valid) return std::string("the estimate is invalid");
  const msg::State& s = *state_;
  if (std::abs(s.phi) > phi_max_()) return fmt::format("|phi| {:.3f} rad > phi_max {:.3f}", std::abs(s.phi), phi_max_());
  if (std::abs(s.theta) > theta_max_()) return fmt::format("|theta| {:.3f} rad > theta_max {:.3f}", std::abs(s.theta), theta_max_());
  if (s.Va < Va_min_()) return fmt::format("Va {:.2f} m/s < Va_min {:.2f}", s.Va, Va_min_());
  if (s.altitude() < h_min_()) return fmt::format("altitude {:.1f} m < h_min {:.1f}", s.altitude(), h_min_());
  return std::nullopt;
}

void SignalGeneratorPlugin::begin_run(Nanos now, bool gated, const std::string& why) {
  try {
    flight_.list = plan();
  } catch (const ParamError& e) {
    log().error("t={:.3f} s: excitation not started: {}", to_seconds(now), e.what());
    return;
  }
  flight_.gated = gated && !Va_sequence_().empty();
  flight_.block = 0;
  flight_.item = 0;
  flight_.steady_since.reset();
  flight_.phase_at_start = phase_.has_value() ? phase_->phase : msg::Phase::cruise;
  log().info("t={:.3f} s: excitation engaged ({}): {} manoeuvre(s){}", to_seconds(now), why, flight_.list.size(),
             flight_.gated ? fmt::format(" at each of {} airspeeds", Va_sequence_().size()) : "");
  if (flight_.gated)
    flight_.run = Run::settling;
  else
    begin_manoeuvre(now);
}

void SignalGeneratorPlugin::begin_manoeuvre(Nanos now) {
  flight_.run = Run::flying;
  flight_.t0 = now;
  const Manoeuvre& m = flight_.list[flight_.item];
  const double Va = state_.has_value() ? state_->Va : 0.0;
  log().info("t={:.3f} s: manoeuvre {} begins: {}, {:.4g} s, at Va {:.2f} m/s", to_seconds(now), flight_.flown, m.describe(), m.duration(),
             Va);
  flight_.marks.emplace_back(fmt::format("m{}_start_s", flight_.flown), to_seconds(now));
}

void SignalGeneratorPlugin::end_manoeuvre(Nanos now) {
  log().info("t={:.3f} s: manoeuvre {} ends", to_seconds(now), flight_.flown);
  flight_.marks.emplace_back(fmt::format("m{}_end_s", flight_.flown), to_seconds(now));
  ++flight_.flown;
  ++flight_.item;
  if (flight_.item < flight_.list.size()) {
    flight_.run = Run::gap;
    flight_.t0 = now + from_seconds(t_gap_());
    return;
  }
  flight_.item = 0;
  ++flight_.block;
  if (flight_.gated && flight_.block < Va_sequence_().size()) {
    flight_.run = Run::settling;
    flight_.steady_since.reset();
    return;
  }
  flight_.run = Run::idle;
  log().info("t={:.3f} s: excitation sequence complete ({} manoeuvres): control handed back", to_seconds(now), flight_.flown);
}

void SignalGeneratorPlugin::abort(Nanos now, const std::string& why) {
  if (!active()) return;
  const bool flying = flight_.run == Run::flying;
  log().warn("t={:.3f} s: excitation aborted{}: {}; control handed back (pass-through)", to_seconds(now),
             flying ? fmt::format(" in manoeuvre {} ({})", flight_.flown, flight_.list[flight_.item].describe()) : std::string(), why);
  if (flying) {
    flight_.marks.emplace_back(fmt::format("m{}_aborted_s", flight_.flown), to_seconds(now));
    ++flight_.flown;
  }
  ++flight_.aborts;
  flight_.run = Run::idle;
}

void SignalGeneratorPlugin::step_surfaces(Nanos now) {
  // Commands: the engage parameter (on a change), the RC switch, then the mission's start.
  if (engage_() != flight_.engage_seen) {
    flight_.engage_seen = engage_();
    if (engage_() == "off") abort(now, "engage set to off");
    if (engage_() == "now" && !active()) begin_run(now, false, "engage set to now");
  }
  if (rc_.has_value() && (rc_->failsafe || rc_->rc_override)) abort(now, rc_->failsafe ? "RC failsafe" : "RC override");
  // The switch engages nothing while the pilot or the receiver's failsafe flies.
  if (rc_channel_() >= 0 && rc_.has_value() && !rc_->failsafe && !rc_->rc_override) {
    const bool high = rc_->aux[static_cast<std::size_t>(rc_channel_())] > 0.5;
    if (high && !flight_.rc_high && !active())
      begin_run(now, false, fmt::format("RC aux {} switch", rc_channel_()));
    else if (!high && flight_.rc_high)
      abort(now, fmt::format("RC aux {} switch off", rc_channel_()));
    flight_.rc_high = high;
  }
  if (active() && phase_.has_value() && phase_->phase != flight_.phase_at_start)
    abort(now, fmt::format("phase {} -> {}", msg::phase_name(flight_.phase_at_start), msg::phase_name(phase_->phase)));
  if (active() && mission_edit_.updated()) abort(now, "mission edit (a failsafe's or an operator's)");
  if (active() && flight_.run != Run::settling)
    if (const auto why = envelope_violation()) abort(now, "envelope: " + *why);

  if (engage_() == "mission" && !flight_.mission_started) {
    if (!flight_.anchor) {
      if (start_phase_() == "flight")
        flight_.anchor = 0;
      else if (phase_.has_value() && phase_->phase == msg::Phase::cruise)
        flight_.anchor = phase_->since;
    }
    if (flight_.anchor && now >= *flight_.anchor + from_seconds(start_time_()) && !active()) {
      flight_.mission_started = true;
      begin_run(now, true, "mission");
    }
  }

  // The run's state machine.
  if (flight_.run == Run::settling) {
    const double Va_target = Va_sequence_()[flight_.block];
    const bool steady = state_.has_value() && state_->valid && std::abs(state_->Va - Va_target) < Va_tolerance_() &&
                        std::abs(state_->phi) < phi_settle_() && !envelope_violation();
    if (!steady)
      flight_.steady_since.reset();
    else if (!flight_.steady_since)
      flight_.steady_since = now;
    if (flight_.steady_since && now - *flight_.steady_since >= from_seconds(t_settle_())) {
      log().info("t={:.3f} s: steady at Va {:.2f} m/s (target {:.2f})", to_seconds(now), state_->Va, Va_target);
      begin_manoeuvre(now);
    }
  } else if (flight_.run == Run::gap && now >= flight_.t0) {
    begin_manoeuvre(now);
  }
  std::array<double, 4> e{};
  if (flight_.run == Run::flying) {
    const Manoeuvre& m = flight_.list[flight_.item];
    const double t = to_seconds(now - flight_.t0);
    if (t >= m.duration())
      end_manoeuvre(now);
    else
      e = m.excitation(t);
  }

  if (!controller_actuators_.has_value()) return;
  msg::Actuators out = *controller_actuators_;
  if (flight_.run == Run::flying) {
    out.delta_a = std::clamp(out.delta_a + e[0], -max_delta_[0], max_delta_[0]);
    out.delta_e = std::clamp(out.delta_e + e[1], -max_delta_[1], max_delta_[1]);
    out.delta_r = std::clamp(out.delta_r + e[2], -max_delta_[2], max_delta_[2]);
    out.delta_t = std::clamp(out.delta_t + e[3], 0.0, 1.0);
  }
  out.stamp = now;
  actuators_.publish(out);
  msg::Actuators x;
  x.stamp = now;
  x.delta_a = e[0];
  x.delta_e = e[1];
  x.delta_r = e[2];
  x.delta_t = e[3];
  excitation_.publish(x);
}

std::vector<std::pair<std::string, double>> SignalGeneratorPlugin::summary() const {
  if (surface_mode_) {
    std::vector<std::pair<std::string, double>> s{{"manoeuvres", flight_.flown}, {"aborts", flight_.aborts}};
    s.insert(s.end(), flight_.marks.begin(), flight_.marks.end());
    return s;
  }
  if (!flight_.engaged) return {{"engaged_s", -1.0}};
  return {{"engaged_s", to_seconds(*flight_.engaged)}, {"base", flight_.base}};
}

}  // namespace tern::signal
