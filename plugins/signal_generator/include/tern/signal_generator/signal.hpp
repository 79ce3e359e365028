// tern/signal_generator/signal.hpp: test signals for tuning one control loop, after ROSplane 2.0's
// rosplane_tuning signal generator (rosplane_tuning/src/signal_generator.cpp: step, square,
// sawtooth, triangle, sine), plus a doublet; and the excitation manoeuvres for system
// identification (chirp, Schroeder multisine, 3-2-1-1, doublet: the second half of this file).
// Plain C++: no tern host types.
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
#include <vector>

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

// ---- Excitation manoeuvres for system identification ------------------------------------------
// After ArduPilot's AP_SystemID (libraries/AP_Math/chirp.cpp; ArduCopter mode_systemid.cpp and
// ArduPlane's systemid, read as a specification: its SID_F_START_HZ, SID_F_STOP_HZ, SID_T_REC,
// SID_T_FADE_IN, SID_T_FADE_OUT are the parameters below) and Klein & Morelli, *Aircraft System
// Identification* (2006), ch. 9 (input design: the 3-2-1-1, the doublet, Schroeder-phased
// multisines). Every shape is in [-1, 1], 0 before t = 0 and after its duration; t in s since the
// manoeuvre began.

/// A logarithmic frequency sweep (ArduPilot's Chirp, without its constant-frequency lead-in):
///   omega(t) = omega_0 exp(B t / T_rec),  B = ln(omega_1 / omega_0),  omega_i = 2 pi f_i
///   w(t)     = window(t) sin(omega_0 T_rec / B (exp(B t / T_rec) - 1))      for 0 <= t <= T_rec
/// window: a half-cosine rise over the first t_fade_in s and fall over the last t_fade_out s
/// (both inside T_rec), 1 between. Ranges: 0 < f_start_hz < f_stop_hz (Hz), t_rec > 0 (s),
/// t_fade_in, t_fade_out >= 0 (s) with t_fade_in + t_fade_out <= t_rec.
struct Chirp {
  double f_start_hz = 0.0;
  double f_stop_hz = 0.0;
  double t_rec = 0.0;
  double t_fade_in = 0.0;
  double t_fade_out = 0.0;
  /// Throws std::invalid_argument naming the parameter and its value when out of range.
  void validate() const;
  double value(double t) const;
  /// The instantaneous frequency f(t) = omega(t) / (2 pi), Hz, for 0 <= t <= T_rec.
  double frequency_hz(double t) const;
  double window(double t) const;
};

/// A Schroeder-phased multisine (Klein & Morelli 9.4; Schroeder, IEEE Trans. Inf. Theory 16, 1970):
/// harmonics k f_0 of f_0 = 1 / T_rec with f_start_hz <= k f_0 <= f_stop_hz, dealt in turn to
/// `n_axes` axes (axis j gets the (j, j + n, j + 2n, ...)th of them), so that the axes' signals
/// are orthogonal over T_rec and several surfaces can be excited in one record. Each axis sums
/// its M harmonics with equal amplitudes and Schroeder's phases phi_m = -pi m (m - 1) / M
/// (m = 1..M), which keep the peak factor low, and is scaled to a peak of 1 over the record.
/// Throws std::invalid_argument when f_stop_hz < f_start_hz, t_rec <= 0, axis >= n_axes, or the
/// band holds fewer than one harmonic per axis (the message names the band and T_rec).
class Multisine {
 public:
  Multisine(double f_start_hz, double f_stop_hz, double t_rec, int n_axes, int axis);
  double value(double t) const;
  double t_rec() const { return t_rec_; }
  /// The harmonic numbers k of this axis (frequencies k / T_rec, Hz).
  const std::vector<int>& harmonics() const { return k_; }
  /// The peak factor of the unscaled sum over the record: peak / (sqrt(2) * rms).
  double peak_factor() const { return peak_factor_; }

 private:
  double raw(double t) const;
  double t_rec_ = 0.0;
  std::vector<int> k_;
  std::vector<double> phase_;
  double scale_ = 1.0;
  double peak_factor_ = 0.0;
};

/// The 3-2-1-1 (Klein & Morelli 9.3, after Koehler 1977): +1 for 3 T_p, -1 for 2 T_p, +1 for
/// T_p, -1 for T_p; duration 7 T_p. T_p > 0 s.
double input_3211(double t, double pulse_width);
/// A doublet: +1 for T_p, -1 for T_p; duration 2 T_p. T_p > 0 s.
double input_doublet(double t, double pulse_width);

}  // namespace tern::signal
