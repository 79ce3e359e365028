// gain_design.cpp: uavbook ch. 6 successive loop closure (see tern/aero/gain_design.hpp).
#include "tern/aero/gain_design.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "tern/aero/model.hpp"
#include "tern/math.hpp"

namespace tern::aero {

std::vector<std::pair<std::string, double>> design_gains(const LinearModel& lm, const DesignOptions& o) {
  const auto& k = lm.tf;
  const double Va = lm.Va, g = tern::kGravity;
  std::vector<std::pair<std::string, double>> out;
  // roll (sec. 6.1.1): closed loop s^2 + (a_phi1 + a_phi2 kd) s + a_phi2 kp
  const double wn_phi = std::isnan(o.wn_phi) ? k.at("a_phi1") / (2 * o.zeta_phi) : o.wn_phi;
  const double roll_kp = wn_phi * wn_phi / k.at("a_phi2");
  const double roll_kd = std::max(0.0, (2 * o.zeta_phi * wn_phi - k.at("a_phi1")) / k.at("a_phi2"));
  out.push_back({"roll_kp", roll_kp});
  out.push_back({"roll_kd", roll_kd});
  out.push_back({"roll_ki", 0.0});
  // roll command shaping (tern): the aileron that sustains a roll rate, fed forward, and the
  // command's slew limit (configs/gains/README.md)
  out.push_back({"roll_ff", k.at("a_phi1") / k.at("a_phi2")});
  out.push_back({"roll_rate_max", o.roll_rate_max});
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

std::vector<std::string> design_summary(const LinearModel& lm, const DesignOptions& o,
                                        const std::vector<std::pair<std::string, double>>& gains) {
  const auto& k = lm.tf;
  auto gain = [&](const char* name) {
    for (const auto& [n, v] : gains)
      if (n == name) return v;
    throw std::runtime_error(std::string("design_summary: no gain ") + name);
  };
  // the slow pole of the roll loop s^2 + s1 s + s0 (kd may be clamped at 0 when a_phi1 is large)
  const double s1 = k.at("a_phi1") + k.at("a_phi2") * gain("roll_kd"), s0 = k.at("a_phi2") * gain("roll_kp");
  const double disc = s1 * s1 - 4 * s0;
  const double w_roll = disc > 0 ? (s1 - std::sqrt(disc)) / 2 : std::sqrt(s0);
  const double kp_th = -gain("pitch_kp"), a2 = k.at("a_theta2"), a3 = k.at("a_theta3");
  char buf[5][200];
  std::snprintf(buf[0], sizeof buf[0], "full-aileron roll rate per rad of aileron a_phi2/a_phi1 = %.3f rad/s",
                k.at("a_phi2") / k.at("a_phi1"));
  std::snprintf(buf[1], sizeof buf[1], "roll_ff = a_phi1/a_phi2 feeds the rate of the roll command forward to the aileron;");
  std::snprintf(buf[2], sizeof buf[2], "roll_rate_max = %g rad/s slew-limits that command", o.roll_rate_max);
  std::snprintf(buf[3], sizeof buf[3], "roll loop wn %.3f rad/s, slowest pole %.3f rad/s, course loop bandwidth %.3f rad/s", std::sqrt(s0),
                w_roll, std::sqrt(s0) / o.W_chi);
  std::snprintf(buf[4], sizeof buf[4], "K_theta_DC = %.4f, pitch loop wn = %.3f rad/s", kp_th * a3 / (a2 + kp_th * a3),
                std::sqrt(a2 + kp_th * a3));
  return {buf[0], buf[1], buf[2], buf[3], buf[4]};
}

}  // namespace tern::aero
