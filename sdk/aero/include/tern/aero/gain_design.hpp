// tern/aero/gain_design.hpp: `tern aero gains` (issue 11): Beard & McLain ch. 6 successive loop closure from
// the ch. 5 transfer-function coefficients, flat control_slc gains. Plain C++, no host types.
#pragma once

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "tern/aero/linear_model.hpp"

namespace tern::aero {

/// Design knobs of the successive loop closure (defaults = configs/gains/*.yaml's design).
struct DesignOptions {
  double wn_phi = std::numeric_limits<double>::quiet_NaN();  ///< NaN: a_phi1/(2 zeta_phi)
  double zeta_phi = 0.8, W_chi = 10.0, T_chi = 25.0, K_theta_DC = 0.7, pitch_ki_ratio = 0.1;
  double zeta_theta = 0.8, W_h = 25.0, zeta_h = 1.0, wn_V = 1.5, zeta_V = 1.0, kr = 0.3, p_wo = 0.5;
  double roll_rate_max = 1.5;  ///< rad/s, slew limit of the roll command (about 0.4 a_phi2 max_a / a_phi1)
};

/// Ordered control_slc parameters (name, value) of uavbook sec. 6.1-6.2, with tern's roll command
/// shaping (roll_ff = a_phi1/a_phi2, roll_rate_max; configs/gains/README.md).
std::vector<std::pair<std::string, double>> design_gains(const LinearModel& lm, const DesignOptions& o);

/// Figures of the design for a gains file's header: full-aileron roll rate, roll loop natural
/// frequency and slowest pole, course bandwidth, pitch loop DC gain and natural frequency.
std::vector<std::string> design_summary(const LinearModel& lm, const DesignOptions& o,
                                        const std::vector<std::pair<std::string, double>>& gains);

}  // namespace tern::aero
