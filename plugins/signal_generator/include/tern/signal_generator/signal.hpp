// tern/signal_generator/signal.hpp: test signals for tuning one control loop, after ROSplane 2.0's
// rosplane_tuning signal generator (rosplane_tuning/src/signal_generator.cpp: step, square,
// sawtooth, triangle, sine), plus a doublet. Plain C++: no tern host types.
//
// A waveform w(t) is a shape in [-1, 1], t in s since the signal started, P the period in s:
//   step      0 for t < P/2, then 1 (held)
//   square    0 for the first half of each period, 1 for the second half
//   sine      (1 - cos(2 pi t / P)) / 2: starts at 0, rises to 1 at P/2 (ROSplane's -cos)
//   triangle  rises linearly from 0 to 1 over the first half period, falls back over the second
//   sawtooth  rises linearly from 0 to 1 over each period, drops back to 0
//   doublet   0 for t < P/2, 1 for P/2 <= t < P, -1 for P <= t < 3P/2, then 0 (held)
// Every waveform starts at 0, so a signal engages at its base value; the first edge of step,
// square and doublet comes P/2 after the start. The command is
//   value = base + offset + amplitude * w(t)
// with base the value the loop was commanded when the signal engaged (or 0, see Reference).
#pragma once

#include <optional>
#include <string_view>

namespace tern::signal {

enum class Waveform { step, square, sine, triangle, sawtooth, doublet };

/// The loop whose command the signal replaces (uavbook symbols of ControllerCommand).
///   roll      phi_c, rad     (the course loop is bypassed: override_phi)
///   pitch     theta_c, rad   (the altitude or energy loop is bypassed: override_theta)
///   course    chi_c, rad
///   altitude  h_c, m
///   airspeed  Va_c, m/s
/// control_slc has no body-rate command input (its roll and pitch loops close on the angle
/// with the rate as damping, Beard & McLain 6.1.1, 6.1.2), so there is no rate loop here.
enum class Loop { roll, pitch, course, altitude, airspeed };

/// Where `base` comes from.
///   command   the loop's command in force when the signal engages (roll and pitch: the
///             controller's inner command, controller_internals; the others: the follower's)
///   absolute  0: the signal is offset + amplitude * w(t)
enum class Reference { command, absolute };

/// w(t) in [-1, 1] for t >= 0 s and period > 0 s; 0 for t < 0.
double waveform(Waveform w, double t, double period);

std::optional<Waveform> waveform_from_name(std::string_view name);
std::optional<Loop> loop_from_name(std::string_view name);
std::optional<Reference> reference_from_name(std::string_view name);
std::string_view loop_name(Loop l);
/// The ControllerCommand field the loop replaces: "phi_c", "theta_c", "chi_c", "h_c", "Va_c".
std::string_view command_symbol(Loop l);
/// SI unit of the loop's command: "rad", "m" or "m/s".
std::string_view loop_unit(Loop l);

}  // namespace tern::signal
