// tern/aero/import.hpp: `tern aero import` (issue 11): VSPAERO stability output (.stab, optional .polar)
// or XFLR5's analysis log of a stability polar, in the layouts the tools' writers produce
// (docs/aircraft-modelling.md) -> tern's coefficient names (per radian, body axes, reference
// S/b/c) -> a tern aircraft file. Every coefficient the tool does not give is reported (Default
// list). Plain C++ (Eigen), no host or plugin types. One reader per file: import_vspaero.cpp,
// import_xflr5.cpp; aircraft_build.cpp builds and writes the aircraft.
//
// Errors: malformed input throws std::runtime_error with one line naming the file and field.
#pragma once

#include <limits>
#include <map>
#include <string>
#include <vector>

#include "tern/aircraft.hpp"

namespace tern::aero {

/// Derivatives read from an aero tool, already in tern's names (C_L_alpha, C_ell_p, ...), per
/// radian, but still in the tool's axes: lateral moments about the stability axes at alpha_ref
/// (XFLR5) or about the body axes (VSPAERO, whose CMl/CMn are -CMx/-CMz of the geometry axes);
/// rate derivatives w.r.t. stability-axis (XFLR5) or body-axis (VSPAERO) rates. Totals at the
/// reference point: "C_L", "C_D", "C_m".
struct ToolDerivatives {
  std::string tool;                       ///< "VSPAERO" or "XFLR5"
  std::string source;                     ///< file name
  double S = 0, b = 0, c = 0;             ///< reference area m^2, span m, chord m (0: not in the file)
  double alpha_ref = 0;                   ///< rad, angle of attack of the analysis
  double rho = 0;                         ///< kg/m^3, density of the analysis (0: not in the file)
  bool rates_in_stability_axes = true;    ///< p, r derivatives w.r.t. stability-axis rates (XFLR5)
  bool moments_in_stability_axes = true;  ///< C_ell, C_n about the stability axes (XFLR5)
  std::map<std::string, double> d;        ///< tern name -> value
  std::vector<std::string> notes;         ///< how the file was read (operating point, control groups, ...)
};

/// Which operating point and control groups of a VSPAERO .stab file to read.
struct VspaeroOptions {
  /// elevator, aileron, rudder (empty: all three automatic). Each entry: "" = automatic (the
  /// case-list control group whose name contains "elev" / "ail" / "rud"), "none", a column name
  /// "ConGrp_<n>", or a control-group name of the case list (case-insensitive); a leading '-'
  /// flips the sign of that group's derivatives.
  std::vector<std::string> controls;
  /// Operating point (Beta_ = 0): NaN = the one nearest zero angle of attack (the first of equals);
  /// else the one with this AoA_ (deg).
  double aoa_deg = std::numeric_limits<double>::quiet_NaN();
};

/// VSPAERO stability file (.stab), as VSPAERO's writer lays it out (VSPAERO 2.x to 7.x, see
/// docs/aircraft-modelling.md): per operating point (blocks starting with a line of '*') the
/// `Name Value Units` header (Sref_, Cref_, Bref_, AoA_ deg, Beta_, Rho_), the case list
/// (`Case Delta Units ...`: control-group names in ConGrp order), the column names (`Coef Total
/// Alpha Beta p q r Mach U ConGrp_1 ...`, or VSPAERO 2's `# Coef Alpha ...` where `Coef` is the
/// base value) with one or two unit rows under them (`per`/`rad`, `deg`, ...: per-degree columns
/// are converted), and rows CFx CFy CFz CMx CMy CMz CL CD CS [CMl CMm CMn]. Lengths are taken as
/// metres; Rho_ is used only if it is a plausible kg/m^3. Throws one line naming file and field.
ToolDerivatives parse_vspaero_stab(const std::string& path, const VspaeroOptions& options = {});

/// Drag from a VSPAERO .polar: the rows at Beta = 0 of the first Mach number (and Re), lift column
/// `CLtot` (VSPAERO 7) or `CL`; C_D_p = mean of `CDo`, Oswald e from least squares CDi = CL^2/(pi e AR).
struct PolarFit {
  double C_D_p = 0, e = 0;
  int rows = 0;
  std::vector<std::string> notes;
};
PolarFit parse_vspaero_polar(const std::string& path, double aspect_ratio);

/// XFLR5 (v6) analysis log of a type 7 stability polar, as XFLR5's panel analysis writes it:
/// `Ref. area = ... m²`, `Ref. span`, `Ref. chord` (any of XFLR5's length units), per control
/// position (`Calculation for control position ...`, the first is read) `Mass= ... kg`, the trim
/// `Alpha=...°` and `VInf = ... m/s`, then `Name= value` pairs of the longitudinal (`Cxu Cxa Czu
/// CLa CLq Cmu Cma Cmq`), lateral (`CYb CYp CYr Clb Clp Clr Cnb Cnp Cnr`) and control (`CXde CYde
/// CZde CLde CMde CNde`: force and roll/pitch/yaw moment derivatives w.r.t. the polar's control
/// variable, per radian) derivatives, stability axes. XFLR5 prints neither the density nor C_L, C_D:
/// tern derives q S = -VInf Zw / CLa, rho = 2 q S / (VInf^2 S), C_L = m g / (q S cos phi), the
/// inviscid C_D = -Cxu / 2; C_m = 0 (XFLR5 trims to zero pitching moment). `control` names what the polar's control variable
/// moves: "elevator", "aileron", "rudder" or "" / "none" (control derivatives not read).
ToolDerivatives parse_xflr5(const std::string& path, const std::string& control = "");

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
  tern::Aircraft aircraft;
  std::vector<Default> defaults;
};

/// Builds a tern aircraft: rotates the lateral derivatives to body axes (beta/control columns
/// T^T d; rate derivatives T^T D T when the rates are stability-axis rates), C_L_0 = C_L -
/// C_L_alpha alpha_ref, C_m_0 likewise, drag from the polar or C_D - C_L^2/(pi e AR). Propulsion,
/// servos and stall data come from `propulsion_from` when given (a tern aircraft file), else the
/// Anaconda's (ROSflight); each is listed in defaults.
ImportResult build_aircraft(const ToolDerivatives& t, const MassProperties& m, const PolarFit* polar, const std::string& name,
                            const std::string& propulsion_from = "");

/// tern aircraft file text (loadable by tern::load_aircraft). `header` lines become comments.
std::string aircraft_yaml(const tern::Aircraft& ac, const std::vector<std::string>& header);

}  // namespace tern::aero
