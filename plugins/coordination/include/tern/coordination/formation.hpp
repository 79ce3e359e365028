// tern/coordination/formation.hpp: leader-follower formation on a common orbit. Plain C++
// (Eigen), no host types.
//
// Every vehicle flies the same orbit (centre c, radius rho, direction lambda: 1 clockwise, -1
// counter-clockwise seen from above) with its own path follower: the orbit-following vector field
// of uavbook sec. 10.3 (Beard & McLain, *Small Unmanned Aircraft*), which holds the aircraft on
// the circle whatever its airspeed. What is left to coordinate is the along-orbit spacing, and
// airspeed alone sets it: follower k (k = 1, 2, ... in the mission's vehicle order, the leader
// left out) should trail the leader by k * spacing metres of arc. Its angular position on the
// orbit is theta = atan2(e - c_e, n - c_n) (rad, the book's orbit angle, sec. 10.3); the arc
// error
//     e_k = rho * wrap_pi(lambda * (theta_leader - theta_k) - k * spacing / rho)       (m)
// is > 0 when the follower is too far behind. The arc error moves with the ground speeds,
// d e_k / dt = Vg_leader - Vg_k, and in a wind w the ground speed along the orbit's tangent
// t(theta) = lambda (-sin theta, cos theta) varies round the circle at one airspeed
// (Vg = ground_speed(Va, w, t), the wind triangle of uavbook sec. 2.3): two aircraft a quarter
// orbit apart in 5 m/s of wind differ by up to ~7 m/s. So the follower is commanded the ground
// speed of the leader (flying Va_nominal at its own place) plus a proportional correction, and
// the airspeed that gives it there in its own wind estimate:
//     Vg_k = ground_speed(Va_nominal, w_leader, t(theta_leader)) + K_s * e_k
//     Va_k = sat(airspeed_for(Vg_k, w_k, t(theta_k)), Va_min, Va_max)               (m/s)
// with K_s (1/s) the spacing gain: e_k then decays with time constant ~1/K_s while unsaturated.
// Without wind it is Va_k = Va_nominal + K_s e_k. (Proportional on airspeed alone, the wind's
// periodic ground-speed difference left 41-62 m RMS of spacing error 300 m behind the leader,
// configs/missions/formation.yaml seeds 1-5.) The wrap keeps the error in [-pi rho, pi rho): a
// follower more than half an orbit off closes the shorter way round.
//
// Why an orbit and not straight lines: on one circle the followers' cross-track is the
// follower's own business (sec. 10.3) and the formation is a one-dimensional spacing problem
// that the airspeed (a mission item's Va_d) reaches; on straight lines of a waypoint mission the
// followers would also need lateral offsets that a path manager's fillets at the corners do not
// keep. Errors: FormationConfig::validate throws std::invalid_argument.
#pragma once

#include "tern/coordination/path_estimate.hpp"

namespace tern::coord {

struct FormationConfig {
  Vec2 center = Vec2::Zero();  ///< orbit centre north, east, m (common frame)
  double radius = 150.0;       ///< rho, m, > 0
  int direction = 1;           ///< lambda: 1 clockwise, -1 counter-clockwise
  double spacing = 100.0;      ///< m of arc between consecutive vehicles, in (0, pi rho)
  double gain = 0.05;          ///< K_s, 1/s, >= 0
  double Va_min = 13.0;        ///< m/s, > 0
  double Va_nominal = 17.0;    ///< m/s, the leader's, in [Va_min, Va_max]
  double Va_max = 22.0;        ///< m/s
  /// Throws std::invalid_argument naming the field when a value is out of range (also when
  /// `followers` followers at `spacing` would need more than one orbit).
  void validate(int followers) const;
};

/// Orbit angle theta (rad, (-pi, pi]) of position p about the centre.
double orbit_angle(const Vec2& p, const Vec2& center);
/// Arc error e_k (m) of follower k >= 1 at angle theta_k behind the leader at theta_leader.
double spacing_error(double theta_leader, double theta_k, int k, const FormationConfig& cfg);
/// Unit tangent (north, east) of the orbit at angle theta in the direction of flight.
Vec2 orbit_tangent(double theta, const FormationConfig& cfg);
/// What the law needs of a vehicle: its orbit angle (rad) and wind estimate (north, east, m/s).
struct OrbitPlace {
  double theta = 0.0;
  Vec2 wind = Vec2::Zero();
};
/// Airspeed command Va_k (m/s) for arc error e (m), the leader and the follower where they are.
double follower_airspeed(double e, const OrbitPlace& leader, const OrbitPlace& follower, const FormationConfig& cfg);

}  // namespace tern::coord
