// tern/aero/model.hpp: the uavbook 6-DOF fixed-wing model (Beard & McLain, *Small Unmanned
// Aircraft*): air data (sec. 2.3), forces and moments (ch. 4 and the propulsion supplement),
// the 13-state equations of motion with a quaternion (ch. 3, appendix B), a ground-contact
// model, and a fixed-step RK4 integrator.
//
// Large angles (where this model leaves the book; at beta = 0 with the flow from ahead, within
// the blending angle, it is the book's, checked term by term in
// plugins/sim_aero/tests/test_sim_aero.cpp). The book's derivatives describe flight; an aircraft
// parked in a crosswind or a tailwind meets flow from the side or from behind, where they would
// give forces no airframe makes (a 7 m/s crosswind at rest: alpha undefined, 26 N of "lift"). So:
//  * Lift, drag and pitching moment act on the flow in the body x-z plane: dynamic pressure
//    qbar cos^2(beta), speed V_xz = Va cos(beta) (the independence principle of yawed wings:
//    R. T. Jones, NACA Report 863, 1947; the spanwise flow makes no lift). A pure crosswind
//    gives side force, not lift. At beta = 0 this is the book's qbar, bit for bit.
//  * The sideslip derivatives hold up to the blending angle (blend_sigma of beta, as for
//    alpha) and fade beyond it: C_Y_beta and C_n_beta to sin(beta) (bounded: the fin and
//    fuselage broadside), C_ell_beta to sin(beta) cos(beta) (the dihedral effect is the wing's
//    change of angle of attack Gamma v_r/u_r at the dynamic pressure of u_r: it scales with
//    u_r v_r and vanishes in a pure crosswind).
//  * Beyond the blending angle of alpha, drag fades to the flat plate and C_m_alpha alpha to
//    C_m_alpha sin(alpha) (drag_coefficient).
//  * The propeller sees the flow along its axis (propeller_inflow): the book's Va in flight,
//    u_r (negative from behind) beyond the blending angle; its drag follows that flow, so a
//    stopped propeller in a tailwind is pushed forward, not pulled aft, and in a crosswind it
//    makes no axial force.
//
// Frames: NED inertial (ground at p_d = 0), FRD body. Units SI. The state vector is
//   x = [p_n p_e p_d  u v w  e0 e1 e2 e3  p q r]  (13 x 1)
// with (u v w) the ground velocity in body axes and e = (e0 scalar) the body -> NED quaternion.
// None of these functions allocate.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "tern/aircraft.hpp"
#include "tern/math.hpp"

namespace tern::sim {

using StateVector = Eigen::Matrix<double, 13, 1>;

/// Index of each state in StateVector.
enum StateIndex : int { PN = 0, PE, PD, U, V, W, E0, E1, E2, E3, P, Q, R };

/// Control inputs (book sec. 4.2 signs): surfaces in rad, throttle 0..1, wheel brakes 0..1.
struct Deltas {
  double delta_e = 0, delta_a = 0, delta_r = 0, delta_t = 0;
  double brake = 0;  ///< the wheels behind the CG brake with mu_brake * brake (Gear)
};

/// Wind acting on the aircraft: steady part in NED plus gust part in body axes (book sec. 4.4).
struct Wind {
  Eigen::Vector3d steady_ned = Eigen::Vector3d::Zero();  ///< m/s
  Eigen::Vector3d gust_body = Eigen::Vector3d::Zero();   ///< m/s
};

/// Airspeed, angle of attack and sideslip (book sec. 2.3, eq. 2.8).
struct AirData {
  Eigen::Vector3d v_air = Eigen::Vector3d::Zero();  ///< (u_r v_r w_r), body, m/s
  double Va = 0, alpha = 0, beta = 0;               ///< m/s, rad, rad (beta = 0 when Va = 0)
  double V_xz = 0;                                  ///< speed of the flow in the body x-z plane, sqrt(u_r^2 + w_r^2) = Va cos(beta), m/s
  /// sin and cos of alpha and beta from the flow's components (w_r / V_xz, u_r / V_xz; v_r / Va,
  /// V_xz / Va: the functions' values to rounding, without a call each)
  double sin_alpha = 0, cos_alpha = 1, sin_beta = 0, cos_beta = 1;
};

/// Propeller speed, thrust and torque (propulsion supplement).
struct PropulsionOutput {
  double Omega = 0;  ///< rad/s, >= 0 (0 when the motor cannot turn the propeller)
  double T_p = 0;    ///< thrust along body x, N
  double Q_p = 0;    ///< propeller torque, N m (enters the rolling moment with a minus sign)
};

/// Everything evaluated at one state: the pieces and the totals, body axes.
struct ForcesMoments {
  AirData air;
  PropulsionOutput prop;
  Eigen::Vector3d f_aero = Eigen::Vector3d::Zero();     ///< aerodynamic + thrust force, N
  Eigen::Vector3d m_aero = Eigen::Vector3d::Zero();     ///< aerodynamic moment - Q_p, N m
  Eigen::Vector3d f_gravity = Eigen::Vector3d::Zero();  ///< m g in body axes, N
  Eigen::Vector3d f_ground = Eigen::Vector3d::Zero();   ///< ground reaction and friction, N
  Eigen::Vector3d m_ground = Eigen::Vector3d::Zero();   ///< N m
  Eigen::Vector3d force = Eigen::Vector3d::Zero();      ///< total, N
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();     ///< total, N m
  int wheels_on_ground = 0;
  /// Specific force an accelerometer measures: (force - f_gravity) / m, m/s^2.
  Eigen::Vector3d specific_force(double mass) const { return (force - f_gravity) / mass; }
};

/// Body -> NED rotation of the (normalised) quaternion part of x.
Eigen::Quaterniond attitude(const StateVector& x);

/// Air data from the body ground velocity and the wind (book sec. 4.4: v_air = v - wind in body axes).
AirData air_data(const StateVector& x, const Wind& wind);
/// Va alone (air_data(x, wind).Va without the angles), m/s.
double airspeed(const StateVector& x, const Wind& wind);

/// Propeller speed, thrust and torque at inflow speed V along body x (m/s; the book's Va, which
/// propeller_inflow gives in flight; negative: flow from behind, whose V^2 terms then push
/// forward) and throttle delta_t (propulsion supplement).
PropulsionOutput propulsion(const Aircraft& ac, double V, double delta_t);

/// The propeller's inflow speed along body x, m/s: (1 - sigma) V_xz + sigma u_r with sigma the
/// blending function at alpha (blend_sigma). In flight (alpha within the blending angle) it is
/// V_xz, i.e. the book's Va at beta = 0; with flow from behind it is u_r < 0, across the disc 0.
double propeller_inflow(const AirData& air, double sigma);

/// Blending angle used when an aircraft has no stall blend (stall_blend false): its linear lift
/// holds up to 0.35 rad (20 deg) of angle of attack, then fades to the flat plate.
inline constexpr double kLinearLiftLimit = 0.35;

/// The book's blending function sigma(alpha) (sec. 4.2) with M and alpha0 (or kLinearLiftLimit
/// when stall_blend is false): ~0 in the linear range, ~1 beyond it.
double blend_sigma(const Aircraft& ac, double alpha);

/// Lift coefficient (book sec. 4.2): (1 - sigma)(C_L_0 + C_L_alpha alpha) + sigma 2 sign(a) sin^2 a cos a.
double lift_coefficient(const Aircraft& ac, double alpha);
/// Drag coefficient: the polar C_D_p + (C_L_0 + C_L_alpha alpha)^2/(pi e AR) of uavbook_model.md
/// while sigma ~ 0; beyond the blending angle it fades, with the same sigma, to the flat plate
/// C_D_p + 2 |sin a|^3 (the drag that goes with the book's flat-plate lift), so that flow from
/// behind (tailwind on the ground, after a stall) gives bounded forces. The pitching moment's
/// C_m_alpha alpha fades likewise to C_m_alpha sin(alpha). Within the usual flight envelope
/// (|alpha| well below the blending angle) the book's model is unchanged.
double drag_coefficient(const Aircraft& ac, double alpha);

/// All forces and moments at state x (gravity, aerodynamics, propulsion, ground contact); at
/// large angles as the header's "Large angles" says.
ForcesMoments forces_moments(const Aircraft& ac, const StateVector& x, const Deltas& d, const Wind& w);

/// The 13-state derivative (book eqs. 3.14-3.17 with the quaternion of appendix B).
/// If fm is given, it receives the forces and moments used.
StateVector derivative(const Aircraft& ac, const StateVector& x, const Deltas& d, const Wind& w, ForcesMoments* fm = nullptr);

/// One classical RK4 step of length dt (s) with inputs and wind held constant; the quaternion
/// is renormalised at the end.
StateVector rk4_step(const Aircraft& ac, const StateVector& x, const Deltas& d, const Wind& w, double dt);

/// Builds a state from position NED, body ground velocity, Euler angles (3-2-1) and body rates.
StateVector make_state(const Eigen::Vector3d& p_ned, const Eigen::Vector3d& v_body, double phi, double theta, double psi,
                       const Eigen::Vector3d& pqr = Eigen::Vector3d::Zero());

/// True if every element is finite.
bool all_finite(const StateVector& x);

/// Height of the CG above the ground (p_d = 0) when the aircraft rests level on its gear
/// (wheels compressed by their static deflection), m.
double rest_height(const Aircraft& ac);

/// The aircraft at rest on its gear at (p_n, p_e) with heading psi, engine off, no wind: the
/// level state at rest_height() settled by integrating the ground model for a few seconds (so
/// that a flight starting on the ground starts without a drop or a rocking transient).
StateVector rest_state(const Aircraft& ac, double p_n, double p_e, double psi);

}  // namespace tern::sim
