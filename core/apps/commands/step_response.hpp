// core/apps/commands/step_response.hpp: the classic step-response figures of one recorded step (rise
// time, overshoot, settling time, steady-state error), for `tern tune`. Plain C++.
//
// Definitions (as MATLAB's stepinfo; Ogata, "Modern Control Engineering", ch. 5), with y0 the
// response at the step, r the command after it and y_f the final value:
//   y_f         the mean response over the last `final_fraction` of the window (the record
//               ends at the next step; averaging keeps sensor noise and turbulence out of it)
//   rise time   from the first crossing of y0 + 10 % (y_f - y0) to the first of y0 + 90 % (y_f - y0), s
//   overshoot   100 * the largest excursion past y_f, away from y0, / |y_f - y0|, %  (0 if none)
//   settling    from the step to the last time |y - y_f| > band * |y_f - y0|, s (band 2 %)
//   ss error    r - y_f, in the loop's unit
// Crossings are interpolated linearly between samples. First order, y = 1 - exp(-t/tau): rise
// 2.197 tau, settling 3.912 tau. Second order, zeta < 1: overshoot exp(-zeta pi / sqrt(1 - zeta^2)).
#pragma once

#include <vector>

namespace tern::core {

struct StepMetrics {
  double y0 = 0.0;                  ///< response at the step
  double y_final = 0.0;             ///< final value y_f
  double rise_time = 0.0;           ///< s; NaN if y never reached 90 % of the way
  double overshoot_pct = 0.0;       ///< %
  double settling_time = 0.0;       ///< s; NaN if the response never stayed in the band
  double steady_state_error = 0.0;  ///< r - y_f
};

/// Figures of one step. `t` (s, increasing, t[0] = the step) and `y` have the same size >= 4;
/// `r` is the command after the step. Throws std::invalid_argument on sizes, a non-increasing
/// t, or y_f == y0 (no step to measure).
StepMetrics step_metrics(const std::vector<double>& t, const std::vector<double>& y, double r, double band = 0.02,
                         double final_fraction = 0.1);

}  // namespace tern::core
