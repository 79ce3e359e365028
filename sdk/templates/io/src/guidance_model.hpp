// guidance_model.hpp: the kinematic guidance model of a fixed-wing aircraft under autopilot
// control (plain C++, no tern types), Beard & McLain, *Small Unmanned Aircraft*, sec. 9.4
// (eq. 9.19, no wind): the autopilot is assumed to make course, altitude and airspeed follow
// their commands as second- and first-order systems,
//   p_n' = Va cos(chi) cos(gamma),  p_e' = Va sin(chi) cos(gamma)
//   chi'' = b_chidot (chidot_c - chi') + b_chi (chi_c - chi)      chidot_c = g tan(phi_ff) / Va
//   h''   = b_hdot (-h') + b_h (h_c - h)                           |h'| <= max_climb_rate
//   Va'   = b_Va (Va_c - Va)
// and reports the roll of a coordinated turn, phi = atan(Va chi' / g) (eq. 9.14), limited to
// +-phi_max (which limits chi'). Units SI, angles rad, NED positions m, h = -p_d.
#pragma once

namespace tern_@NAME@ {

struct ModelGains {
  double b_chi = 1.0;      ///< 1/s^2 (course loop natural frequency squared)
  double b_chidot = 1.8;   ///< 1/s
  double b_h = 0.25;       ///< 1/s^2
  double b_hdot = 0.9;     ///< 1/s
  double b_Va = 0.5;       ///< 1/s
  double phi_max = 0.7;    ///< rad, roll limit of the coordinated turn
  double max_climb_rate = 5.0;  ///< m/s
};

struct ModelState {
  double p_n = 0.0, p_e = 0.0, h = 100.0;  ///< position: north, east (m), height above the origin (m)
  double chi = 0.0, chi_dot = 0.0;         ///< course (rad) and its rate (rad/s)
  double h_dot = 0.0;                      ///< climb rate, m/s
  double Va = 17.0;                        ///< airspeed, m/s
};

struct ModelCommand {
  double chi_c = 0.0, h_c = 100.0, Va_c = 17.0, phi_ff = 0.0;
};

class GuidanceModel {
 public:
  GuidanceModel() = default;
  explicit GuidanceModel(const ModelGains& g) : g_(g) {}
  void set_gains(const ModelGains& g) { g_ = g; }
  void set_state(const ModelState& x) { x_ = x; }
  const ModelState& state() const { return x_; }

  /// Advances dt seconds (> 0) with the command held (semi-implicit Euler in sub-steps of at
  /// most 10 ms). A non-finite command leaves the previous command in force.
  void step(const ModelCommand& c, double dt);

  /// Roll (rad) of the coordinated turn at the current course rate.
  double phi() const;
  /// Flight-path angle (rad).
  double gamma() const;

 private:
  ModelGains g_;
  ModelState x_;
  ModelCommand last_{};
};

}  // namespace tern_@NAME@
