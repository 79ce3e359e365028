// aero_pipeline.hpp: the aerodynamic modelling pipeline of `tern aero import|linearize|gains`
// (issue 11). Plain C++ (Eigen), no host or plugin types.
//
//  * import: VSPAERO stability output (.stab, optional .polar) or XFLR5 stability-analysis text
//    output -> tern's coefficient names (per radian, body axes, reference S/b/c) -> a tern
//    aircraft file. Every coefficient the tool does not give is reported (Default list).
//  * linearize: Beard & McLain ch. 5 state-space models about a trim (central differences of
//    sim_aero's nonlinear model) and the transfer-function coefficients of sec. 5.4.
//  * design_gains: Beard & McLain ch. 6 successive loop closure (the design of
//    plugins/control_slc/tools/design_gains.py, same defaults), flat control_slc gains.
//
// Errors: malformed input throws std::runtime_error with one line naming the file and field.
#pragma once

#include <limits>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tern_sim_aero/aircraft.hpp"
#include "tern_sim_aero/trim.hpp"

namespace tern::aero {

/// Derivatives read from an aero tool, already in tern's names (C_L_alpha, C_ell_p, ...), per
/// radian, but still in the tool's axes (`stability_axes`: lateral moments about the stability
/// axes at alpha_ref). Totals at the reference point: "C_L", "C_D", "C_m".
struct ToolDerivatives {
  std::string tool;                 ///< "VSPAERO" or "XFLR5"
  std::string source;               ///< file name
  double S = 0, b = 0, c = 0;       ///< reference area m^2, span m, chord m (0: not in the file)
  double alpha_ref = 0;             ///< rad, angle of attack of the analysis
  double rho = 0;                   ///< kg/m^3, density of the analysis (0: not in the file)
  bool rates_in_stability_axes = true;  ///< p, r derivatives w.r.t. stability-axis rates (XFLR5)
  std::map<std::string, double> d;  ///< tern name -> value
};

/// VSPAERO .stab (text): the `Name Value Units` header block (Sref_, Cref_, Bref_, AoA_ in deg)
/// and the derivative table (rows CFx..CMn; columns Total, Alpha, Beta, p, q, r, Mach, U and
/// one per control group, with a unit row "per rad" / "per deg": per-degree columns are
/// converted). Control groups: controls[0..2] name the elevator, aileron, rudder columns.
ToolDerivatives parse_vspaero_stab(const std::string& path,
                                   const std::vector<std::string>& controls = {"ConGrp_1", "ConGrp_2",
                                                                               "ConGrp_3"});

/// Drag from a VSPAERO .polar: C_D_p = mean of CDo, Oswald e from least squares CDi = CL^2/(pi e AR).
struct PolarFit {
  double C_D_p = 0, e = 0;
  int rows = 0;
};
PolarFit parse_vspaero_polar(const std::string& path, double aspect_ratio);

/// XFLR5 stability-analysis text output: `Name= value` pairs (CLa, CLq, Cma, Cmq, CYb, CYp, CYr,
/// Clb, Clp, Clr, Cnb, Cnp, Cnr; control derivatives CLde, Cmde, CYda, Clda, Cnda, CYdr, Cldr,
/// Cndr; the operating point Alpha (deg), CL, CD, Cm; reference lines with "ref", "mean" or
/// "wing" and "area", "span" or "chord" before the '='). Derivatives per radian, stability axes.
ToolDerivatives parse_xflr5(const std::string& path);

struct MassProperties {
  double mass = 0, Jx = 0, Jy = 0, Jz = 0, Jxz = 0;
};
/// Reads `mass:` and `inertia: {Jx, Jy, Jz, Jxz}` from a YAML file (a tern aircraft file works).
MassProperties load_mass_file(const std::string& path);

/// One coefficient the tool did not provide: the value used and why.
struct Default {
  std::string name;
  double value = 0;  ///< NaN for a group of values (then `why` says where they come from)
  std::string why;
};

struct ImportResult {
  sim::Aircraft aircraft;
  std::vector<Default> defaults;
};

/// Builds a tern aircraft: rotates the lateral derivatives to body axes (beta/control columns
/// T^T d; rate derivatives T^T D T when the rates are stability-axis rates), C_L_0 = C_L -
/// C_L_alpha alpha_ref, C_m_0 likewise, drag from the polar or C_D - C_L^2/(pi e AR). Propulsion,
/// servos and stall data come from `propulsion_from` when given (a tern aircraft file), else the
/// Anaconda's (ROSflight); each is listed in defaults.
ImportResult build_aircraft(const ToolDerivatives& t, const MassProperties& m, const PolarFit* polar,
                            const std::string& name, const std::string& propulsion_from = "");

/// tern aircraft file text (loadable by sim::load_aircraft). `header` lines become comments.
std::string aircraft_yaml(const sim::Aircraft& ac, const std::vector<std::string>& header);

/// Beard & McLain ch. 5 linear models and transfer-function coefficients.
struct LinearModel {
  sim::TrimResult trim;
  double Va = 0;
  // x_lon = [u w q theta h], u_lon = [delta_e delta_t]; x_lat = [v p r phi psi], u_lat = [delta_a delta_r]
  Eigen::Matrix<double, 5, 5> A_lon, A_lat;
  Eigen::Matrix<double, 5, 2> B_lon, B_lat;
  std::map<std::string, double> tf;  ///< a_phi1, a_phi2, a_theta1..3, a_V1..3, a_beta1, a_beta2
};
LinearModel linearize(const sim::Aircraft& ac, const sim::TrimRequest& req);

/// Design knobs of the successive loop closure (defaults = configs/gains/*.yaml's design).
struct DesignOptions {
  double wn_phi = std::numeric_limits<double>::quiet_NaN();  ///< NaN: a_phi1/(2 zeta_phi)
  double zeta_phi = 0.8, W_chi = 5.5, T_chi = 25.0, K_theta_DC = 0.7, pitch_ki_ratio = 0.1;
  double zeta_theta = 0.8, W_h = 25.0, zeta_h = 1.0, wn_V = 1.5, zeta_V = 1.0, kr = 0.3, p_wo = 0.5;
};
/// Ordered control_slc parameters (name, value) of uavbook sec. 6.1-6.2.
std::vector<std::pair<std::string, double>> design_gains(const LinearModel& lm, const DesignOptions& o);

}  // namespace tern::aero
