// gain_design.cpp: uavbook ch. 6 successive loop closure (see gain_design.hpp).
#include "gain_design.hpp"

#include <algorithm>
#include <cmath>

#include "tern_sim_aero/model.hpp"

namespace tern::aero {

std::vector<std::pair<std::string, double>> design_gains(const LinearModel& lm, const DesignOptions& o) {
  const auto& k = lm.tf;
  const double Va = lm.Va, g = sim::kG;
  std::vector<std::pair<std::string, double>> out;
  // roll (sec. 6.1.1): closed loop s^2 + (a_phi1 + a_phi2 kd) s + a_phi2 kp
  const double wn_phi = std::isnan(o.wn_phi) ? k.at("a_phi1") / (2 * o.zeta_phi) : o.wn_phi;
  const double roll_kp = wn_phi * wn_phi / k.at("a_phi2");
  const double roll_kd = std::max(0.0, (2 * o.zeta_phi * wn_phi - k.at("a_phi1")) / k.at("a_phi2"));
  out.push_back({"roll_kp", roll_kp});
  out.push_back({"roll_kd", roll_kd});
  out.push_back({"roll_ki", 0.0});
  // course (sec. 6.1.2): P bandwidth wn_phi / W_chi, slow integrator T_chi
  const double wc = std::sqrt(k.at("a_phi2") * roll_kp) / o.W_chi;
  const double course_kp = wc * Va / g;
  out.push_back({"course_kp", course_kp});
  out.push_back({"course_ki", course_kp / o.T_chi});
  out.push_back({"course_kd", 0.0});
  // pitch (sec. 6.2.1); tern's pitch gains are magnitudes (the book's are negative)
  const double a1 = k.at("a_theta1"), a2 = k.at("a_theta2"), a3 = k.at("a_theta3");
  const double kp_th = o.K_theta_DC * a2 / ((1 - o.K_theta_DC) * a3);
  const double wn_th = std::sqrt(a2 + kp_th * a3);
  const double kd_th = (2 * o.zeta_theta * wn_th - a1) / a3;
  const double K_dc = kp_th * a3 / (a2 + kp_th * a3);
  out.push_back({"pitch_kp", -kp_th});
  out.push_back({"pitch_kd", std::max(0.0, -kd_th)});
  out.push_back({"pitch_ki", o.pitch_ki_ratio * (-kp_th) * wn_th});
  // altitude from pitch (sec. 6.2.2, eq. 6.24)
  const double wn_h = wn_th / o.W_h;
  out.push_back({"altitude_ki", wn_h * wn_h / (K_dc * Va)});
  out.push_back({"altitude_kp", 2 * o.zeta_h * wn_h / (K_dc * Va)});
  out.push_back({"altitude_kd", 0.0});
  // airspeed with throttle (sec. 6.2.4, eq. 6.29)
  out.push_back({"airspeed_ki", o.wn_V * o.wn_V / k.at("a_V2")});
  out.push_back({"airspeed_kp", std::max(0.0, (2 * o.zeta_V * o.wn_V - k.at("a_V1")) / k.at("a_V2"))});
  out.push_back({"airspeed_kd", 0.0});
  // yaw damper (sec. 6.1.3)
  out.push_back({"yaw_damper_kr", o.kr});
  out.push_back({"yaw_damper_p_wo", o.p_wo});
  out.push_back({"trim_e", lm.trim.delta.delta_e});
  out.push_back({"trim_t", lm.trim.delta.delta_t});
  return out;
}

}  // namespace tern::aero
