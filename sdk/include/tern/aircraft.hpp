// tern/aircraft.hpp: the parameters of a fixed-wing aircraft for the uavbook model (Beard &
// McLain, *Small Unmanned Aircraft*, ch. 3-4 and the propulsion supplement), and the one reader
// of aircraft files: the simulator (sim_aero), the estimator (estimator_ekf), the flight
// controller link (fcu_serial) and the campaigns (core/apps/campaign) read the file through it.
//
// Two file formats are read:
//  * tern's own format (configs/aircraft/*.yaml): sections mass/inertia/environment/wing/aero/
//    propulsion/servos/gear with the book's symbols (C_L_0, C_m_alpha, ...), SI units
//    (documented field by field in configs/aircraft/anaconda.yaml);
//  * ROSflight simulator files (`*_dynamics.yaml`), unchanged: ROS 2 `<node>: ros__parameters:`
//    nesting under the nodes `/**`, `/fixedwing_forces_and_moments` and `/standalone_dynamics`,
//    ROSflight's coefficient names (C_L_O, CT_0, KQ, wing_s, Jxx, ...), deflection limits in
//    degrees, and the ROSflight drag polar (C_D_p, Oswald factor fixed at 0.9 as ROSflight does).
//    As ROSflight's simulator does with these files, the lift is linear (no stall blend: its
//    sigma(alpha) is set to 0; the Anaconda's wing_alpha0 of 3 deg would otherwise stall it at
//    cruise); wing_epsilon, servo_refresh_rate and the *_channel keys are read and not used.
//
// Errors: every problem (file missing, malformed YAML, unknown key, missing required field,
// non-finite or out-of-range value such as a negative mass or inertia, a value no small aircraft
// has, such as a coefficient of 2.7e300 or an air density in g/m^3: the plausible ranges are
// in sdk/src/aircraft.cpp) throws std::runtime_error with one line "<file>:<line>: <field>: <what is
// wrong>" (no line for a document built in code, or for a problem of several fields).
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "tern/export.hpp"

namespace YAML {
class Node;
}

namespace tern {

/// Aerodynamic coefficients of the uavbook model (book section 4.2, symbols as in the book).
/// Dimensionless; rates are normalised by c/(2 Va) (longitudinal) or b/(2 Va) (lateral).
struct AeroCoefficients {
  // longitudinal
  double C_L_0 = 0, C_L_alpha = 0, C_L_q = 0, C_L_delta_e = 0;
  double C_D_0 = 0, C_D_alpha = 0;  ///< linear drag model: kept for the ch. 5 linear models only
  double C_D_p = 0;                 ///< parasitic drag of the polar C_D = C_D_p + C_L^2/(pi e AR)
  double C_D_q = 0, C_D_delta_e = 0;
  double C_m_0 = 0, C_m_alpha = 0, C_m_q = 0, C_m_delta_e = 0;
  // lateral
  double C_Y_0 = 0, C_Y_beta = 0, C_Y_p = 0, C_Y_r = 0, C_Y_delta_a = 0, C_Y_delta_r = 0;
  double C_ell_0 = 0, C_ell_beta = 0, C_ell_p = 0, C_ell_r = 0, C_ell_delta_a = 0, C_ell_delta_r = 0;
  double C_n_0 = 0, C_n_beta = 0, C_n_p = 0, C_n_r = 0, C_n_delta_a = 0, C_n_delta_r = 0;
};

/// Motor and propeller (uavbook propulsion supplement to ch. 4).
struct Propulsion {
  double D_prop = 0;                       ///< propeller diameter, m
  double C_T_0 = 0, C_T_1 = 0, C_T_2 = 0;  ///< thrust coefficient C_T(J) = C_T_2 J^2 + C_T_1 J + C_T_0
  double C_Q_0 = 0, C_Q_1 = 0, C_Q_2 = 0;  ///< torque coefficient C_Q(J), same form
  double K_V = 0;                          ///< motor speed constant, RPM/V (informative)
  double K_Q = 0;                          ///< torque constant, N m/A; also the back-EMF constant in V s/rad
  double R_motor = 0;                      ///< winding resistance, ohm
  double i0 = 0;                           ///< no-load current, A
  double V_max = 0;                        ///< battery voltage at full throttle, V
};

/// One landing-gear contact point (wheel bottom) in the body frame FRD about the CG, m.
using ContactPoint = Eigen::Vector3d;

/// Ground contact: spring-damper wheels with rolling and lateral friction.
struct Gear {
  std::vector<ContactPoint> points;  ///< body FRD, m (z > 0: below the CG)
  double static_deflection = 0.02;   ///< wheel compression at rest with the weight shared evenly, m
  double damping_ratio = 1.0;        ///< per wheel, of the heave mode (>= 1: no bounce)
  double mu_roll = 0.03;             ///< rolling friction coefficient along the wheel
  double mu_lateral = 0.5;           ///< side friction coefficient across the wheel
  double v_slip = 0.1;               ///< speed below which friction is viscous (no chatter at rest), m/s
  /// Nose-wheel steering linked to the rudder: wheels ahead of the CG turn by
  /// -nose_steering * delta_r (positive rudder yaws the nose left, so does the wheel), rad/rad.
  /// 0: no steering (a castoring or fixed wheel).
  double nose_steering = 0.0;
  /// Braking friction coefficient of the wheels behind the CG at full brake (added to mu_roll;
  /// viscous below v_slip like it, so that a braked aircraft holds still). 0.4: a small rubber
  /// wheel braked on grass or tarmac (tyre-ground friction 0.4-0.7 dry; a hobby brake locks less).
  double mu_brake = 0.4;
  /// A wheel touching down faster than this (its vertical speed at first contact, m/s) breaks the
  /// gear: the simulator's crash "hard touchdown". 3 m/s: a foam RC trainer's gear survives a
  /// drop of ~0.5 m (sqrt(2 g 0.5) = 3.1 m/s); FAR 23.473 designs full-size gear for ~3 m/s.
  double max_sink_rate = 3.0;
  /// Hard points that must never touch the ground (wing tips, nose, tail), body FRD about the CG,
  /// m, with names for the crash message. Default (no `structure` in the file): the wing tips at
  /// (0, +-b/2, 0), the nose at (0.3 b, 0, 0) and the tail at (-0.5 b, 0, -0.06 b) (a small UAV's
  /// fuselage is ~0.8 of its span; the tail sits as far above the CG as the default wheels below
  /// it: a tail strike at ~14 deg of pitch on the main wheels).
  std::vector<std::pair<std::string, ContactPoint>> structure;
};

/// Everything the uavbook model needs to know about one aircraft. Units SI, frames FRD.
struct Aircraft {
  std::string name;
  std::string source;                      ///< file it was loaded from (for messages)
  double mass = 0;                         ///< kg, > 0
  double Jx = 0, Jy = 0, Jz = 0, Jxz = 0;  ///< kg m^2 about the CG (book's J with -Jxz off-diagonal)
  double rho = 0;                          ///< air density used by the aerodynamic model, kg/m^3
  double S = 0;                            ///< wing area, m^2
  double b = 0;                            ///< span, m
  double c = 0;                            ///< mean chord, m
  double e = 0.9;                          ///< Oswald efficiency of the drag polar
  double M = 0;                            ///< blending rate of the stall model
  double alpha0 = 0;                       ///< stall angle of the blending function, rad
  /// Blend linear and flat-plate lift with sigma(alpha) (book sec. 4.2). false: linear lift
  /// C_L_0 + C_L_alpha alpha only (sigma = 0), as ROSflight's simulator computes it.
  bool stall_blend = true;
  AeroCoefficients aero;
  Propulsion prop;
  double servo_tau = 0.0;  ///< first-order servo time constant, s (0: no lag)
  /// s, >= 0: aileron, elevator, rudder: the dead time between a command and the surface's first move
  /// (servos.delay_a, delay_e, delay_r; 0 each by default). Read by tern sysid and tern validate,
  /// which pair each logged command with the motion it makes (tern sysid --command-delay writes them);
  /// sim_aero's servos do not delay (their lag is servo_tau).
  double servo_delay_a = 0.0, servo_delay_e = 0.0, servo_delay_r = 0.0;
  double max_delta_a = 0.785398, max_delta_e = 0.785398, max_delta_r = 0.785398;  ///< rad
  Gear gear;

  double AR() const { return b * b / S; }  ///< aspect ratio
};

/// The inertia's Gamma coefficients of the rotational equations (Beard & McLain, eq. 3.13), with
/// Gamma = J_x J_z - J_xz^2: p_dot = G1 p q - G2 q r + G3 l + G4 n,
/// q_dot = G5 p r - G6 (p^2 - r^2) + m / J_y, r_dot = G7 p q - G1 q r + G4 l + G8 n.
struct InertiaGammas {
  double G1, G2, G3, G4, G5, G6, G7, G8;
};
inline InertiaGammas inertia_gammas(const Aircraft& ac) {
  const double G = ac.Jx * ac.Jz - ac.Jxz * ac.Jxz;
  return {ac.Jxz * (ac.Jx - ac.Jy + ac.Jz) / G,
          (ac.Jz * (ac.Jz - ac.Jy) + ac.Jxz * ac.Jxz) / G,
          ac.Jz / G,
          ac.Jxz / G,
          (ac.Jz - ac.Jx) / ac.Jy,
          ac.Jxz / ac.Jy,
          ((ac.Jx - ac.Jy) * ac.Jx + ac.Jxz * ac.Jxz) / G,
          ac.Jx / G};
}

/// Loads an aircraft file (tern or ROSflight format, detected from its content).
/// Throws std::runtime_error "<path>: <field>: <problem>".
TERN_API Aircraft load_aircraft(const std::string& path);

/// Same, from an already parsed document; `source` names it in error messages.
TERN_API Aircraft parse_aircraft(const YAML::Node& doc, const std::string& source);

/// Checks ranges (positive mass, inertia, geometry, J_x J_z > J_xz^2, finite values, limits);
/// throws std::runtime_error naming the field. Called by the loaders.
TERN_API void validate_aircraft(const Aircraft& ac);

/// Default gear when a file names none: a tricycle scaled by the span b (nose 0.15 b ahead,
/// mains 0.03 b behind the CG at +-0.1 b, wheels 0.06 b below the CG).
TERN_API std::vector<ContactPoint> default_gear_points(double b);

/// The default hard points of span b (m): Gear::structure's comment.
TERN_API std::vector<std::pair<std::string, ContactPoint>> default_structure(double b);

}  // namespace tern
