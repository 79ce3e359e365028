#include "guidance_model.hpp"

#include <algorithm>
#include <cmath>
#include "tern/math.hpp"

namespace tern_@NAME@ {
using tern::kGravity;
using tern::wrap_pi;

void GuidanceModel::step(const ModelCommand& c, double dt) {
  if (std::isfinite(c.chi_c) && std::isfinite(c.h_c) && std::isfinite(c.Va_c) && std::isfinite(c.phi_ff)) last_ = c;
  if (!(dt > 0.0) || !std::isfinite(dt)) return;
  const int n = static_cast<int>(std::ceil(dt / 0.01));
  const double h = dt / n;
  for (int k = 0; k < n; ++k) {
    const double Va = std::max(x_.Va, 1.0);
    const double chi_dot_max = kGravity * std::tan(g_.phi_max) / Va;
    const double chidot_c = kGravity * std::tan(std::clamp(last_.phi_ff, -g_.phi_max, g_.phi_max)) / Va;
    const double e_chi = wrap_pi(last_.chi_c - x_.chi);  // the short way round
    const double chi_ddot = g_.b_chidot * (chidot_c - x_.chi_dot) + g_.b_chi * e_chi;
    const double h_ddot = -g_.b_hdot * x_.h_dot + g_.b_h * (last_.h_c - x_.h);
    const double Va_dot = g_.b_Va * (last_.Va_c - x_.Va);
    x_.chi_dot = std::clamp(x_.chi_dot + h * chi_ddot, -chi_dot_max, chi_dot_max);
    x_.h_dot = std::clamp(x_.h_dot + h * h_ddot, -g_.max_climb_rate, g_.max_climb_rate);
    x_.Va = std::max(x_.Va + h * Va_dot, 0.0);
    x_.chi = wrap_pi(x_.chi + h * x_.chi_dot);
    x_.h += h * x_.h_dot;
    const double gamma_k = this->gamma();
    x_.p_n += h * x_.Va * std::cos(x_.chi) * std::cos(gamma_k);
    x_.p_e += h * x_.Va * std::sin(x_.chi) * std::cos(gamma_k);
  }
}

double GuidanceModel::phi() const {
  return std::clamp(std::atan(std::max(x_.Va, 1.0) * x_.chi_dot / kGravity), -g_.phi_max, g_.phi_max);
}

double GuidanceModel::gamma() const {
  return x_.Va > 1.0 ? std::asin(std::clamp(x_.h_dot / x_.Va, -1.0, 1.0)) : 0.0;
}

}  // namespace tern_@NAME@
