// Tests of the modelling pipeline of `tern aero import|linearize|gains` (issue 11).
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <string>
#include <vector>
#include <unistd.h>

#include <Eigen/Eigenvalues>
#include <yaml-cpp/yaml.h>

#include "tern/aero/pipeline.hpp"
#include "tern/aircraft.hpp"
#include "tern/math.hpp"

namespace sim = tern::sim;
namespace aero = tern::aero;
using doctest::Approx;

namespace {

const std::string kData = TERN_AERO_SAMPLES_DIR;
const std::string kAircraft = TERN_AIRCRAFT_DIR;
using tern::kPi;

bool listed(const aero::ImportResult& r, const std::string& name) {
  for (const auto& d : r.defaults)
    if (d.name == name) return true;
  return false;
}

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("tern_aero_test_" + std::to_string(::getpid()) + "_" + name);
}

// One operating point in VSPAERO's (>= 6) .stab layout, written by the tests: the header, the case
// list (control-group names), the column names with VSPAERO's two unit rows ("per" / "rad" or, for
// the control groups, `group_unit`), and the rows CFx .. CMn (values per column: Total Alpha Beta p
// q r Mach U and one per group; rows not given are zeros).
std::string vspaero_stab(double aoa_deg, const std::vector<std::string>& groups, const std::string& group_unit,
                         const std::map<std::string, std::vector<double>>& rows, double S = 0.52, double c = 0.235, double b = 2.08,
                         double rho = 1.225) {
  std::ostringstream o;
  o << std::setprecision(12);
  o << std::string(185, '*') << " \n\n# Name                   Value      Units\n"
    << "Sref_ " << S << " Lunit^2\nCref_ " << c << " Lunit\nBref_ " << b << " Lunit\nXcg_ 0.1 Lunit\n"
    << "Mach_ 0.05 no_unit\nAoA_ " << aoa_deg << " deg\nBeta_ 0 deg\nRho_ " << rho << " Munit/Lunit^3\n"
    << "Vinf_ 17 Lunit/Tunit\n\n#\nCase Delta Units CFx CFy CFz CMx CMy CMz CL CD CS CMl CMm CMn\n#\n";
  std::vector<std::string> cases = {
      "Base_Aero +0.000 n/a",        "Alpha +0.010 deg",   "Beta +0.010 deg", "Roll__Rate +0.010 rad/Tunit", "Pitch_Rate +0.010 rad/Tunit",
      "Yaw___Rate +0.010 rad/Tunit", "Mach +0.100 no_unit"};
  for (const auto& g : groups) cases.push_back(g + " +0.100 deg");
  for (const auto& cs : cases) o << cs << " 0 0 0 0 0 0 0 0 0 0 0 0\n";
  o << "#\n#\n#             Base    Derivative:\n#             Aero wrt\nCoef Total Alpha Beta p q r Mach U";
  for (std::size_t i = 0; i < groups.size(); ++i) o << " ConGrp_" << i + 1;
  o << "\n#  -  per per per per per per per";
  for (std::size_t i = 0; i < groups.size(); ++i) o << " per";
  o << "\n#  -  rad rad rad rad rad M u";
  for (std::size_t i = 0; i < groups.size(); ++i) o << " " << group_unit;
  o << "\n#\n";
  for (const char* r : {"CFx", "CFy", "CFz", "CMx", "CMy", "CMz", "CL", "CD", "CS", "CMl", "CMm", "CMn"}) {
    o << r;
    auto it = rows.find(r);
    for (std::size_t k = 0; k < 8 + groups.size(); ++k) o << " " << (it != rows.end() && k < it->second.size() ? it->second[k] : 0.0);
    o << "\n";
  }
  o << "#\n#\n#\n# Result Value Units\nSM 0.1 no_unit\nX_np 0.12 Lunit\n#\n";
  return o.str();
}

void write_file(const std::filesystem::path& p, const std::string& text) {
  std::ofstream f(p);
  f << text;
}

std::string read_file(const std::string& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// The message of the exception `f` throws (empty if none).
template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("VSPAERO .stab (VSPAERO 6/7 layout): operating point, control groups by case-list name, body axes") {
  const std::string stab = kData + "/sample_vspaero.stab";
  const auto t = aero::parse_vspaero_stab(stab);
  CHECK(t.S == Approx(0.52));
  CHECK(t.b == Approx(2.08));
  CHECK(t.c == Approx(0.235));
  CHECK(t.alpha_ref == Approx(2.0 * kPi / 180.0));  // the one nearest zero of the two (AoA_ 2 and 4)
  CHECK(t.rho == Approx(1.225));
  CHECK_FALSE(t.moments_in_stability_axes);
  CHECK_FALSE(t.rates_in_stability_axes);
  CHECK(t.d.at("C_L") == Approx(0.602));
  CHECK(t.d.at("C_L_alpha") == Approx(5.2741));
  CHECK(t.d.at("C_m_q") == Approx(-30.54));
  // ConGrp_1 = Ailerons, ConGrp_2 = Elevator, ConGrp_3 = Rudder in the case list; per rad
  CHECK(t.d.at("C_L_delta_e") == Approx(0.1301));
  CHECK(t.d.at("C_m_delta_e") == Approx(-0.9912));
  CHECK(t.d.at("C_ell_delta_a") == Approx(0.1702));
  CHECK(t.d.at("C_Y_delta_r") == Approx(0.1891));
  CHECK(t.d.at("C_n_delta_r") == Approx(-0.0693));
  CHECK(t.d.at("C_ell_p") == Approx(-0.465));  // the 4-degree point has -0.5115
  REQUIRE(t.notes.size() >= 2);
  CHECK(t.notes[0].find("operating point: AoA_ 2 deg") != std::string::npos);
  CHECK(t.notes[0].find("nearest zero angle of attack of the 2 in the file") != std::string::npos);

  aero::VspaeroOptions at4;
  at4.aoa_deg = 4.0;
  const auto t4 = aero::parse_vspaero_stab(stab, at4);
  CHECK(t4.alpha_ref == Approx(4.0 * kPi / 180.0));
  CHECK(t4.d.at("C_L") == Approx(0.602 + 5.2741 * 2.0 * kPi / 180.0));
  CHECK(t4.d.at("C_ell_p") == Approx(-0.465 * 1.1));
  at4.aoa_deg = 3.0;
  CHECK_THROWS_WITH_AS(aero::parse_vspaero_stab(stab, at4), doctest::Contains("operating point: none at AoA_ = 3 deg and Beta_ = 0"),
                       std::runtime_error);

  // groups named by the user: case-list names (any case), ConGrp_<n>, "none", a '-' flips the sign
  aero::VspaeroOptions named;
  named.controls = {"-elevator", "ConGrp_1", "none"};
  const auto tn = aero::parse_vspaero_stab(stab, named);
  CHECK(tn.d.at("C_L_delta_e") == Approx(-0.1301));
  CHECK(tn.d.at("C_ell_delta_a") == Approx(0.1702));
  CHECK_FALSE(tn.d.count("C_n_delta_r"));
  named.controls = {"Flaps", "", ""};
  CHECK_THROWS_WITH_AS(aero::parse_vspaero_stab(stab, named),
                       doctest::Contains("elevator control group 'Flaps': not in the case list (ConGrp_1 = Ailerons"), std::runtime_error);

  const aero::PolarFit pf = aero::parse_vspaero_polar(kData + "/sample_vspaero.polar", 2.08 * 2.08 / 0.52);
  CHECK(pf.rows == 6);  // the two rows at Beta = 5 are not used
  CHECK(pf.C_D_p == Approx(0.028));
  CHECK(pf.e == Approx(0.85).epsilon(1e-6));
  const aero::PolarFit pf6 = aero::parse_vspaero_polar(kData + "/sample_vspaero_v6.polar", 2.08 * 2.08 / 0.52);
  CHECK(pf6.rows == 6);
  CHECK(pf6.e == Approx(pf.e).epsilon(1e-9));

  const aero::MassProperties m = aero::load_mass_file(kData + "/sample_mass.yaml");
  CHECK(m.mass == 4.5);
  CHECK(m.Jxz == 0.06);
  const auto r = aero::build_aircraft(t, m, &pf, "trainer");
  const auto& a = r.aircraft.aero;
  CHECK(a.C_L_0 == Approx(0.602 - 5.2741 * 0.0349065850).epsilon(1e-8));
  CHECK(a.C_m_0 == Approx(0.0872 + 2.512 * 0.0349065850).epsilon(1e-8));
  // VSPAERO's CMl = -CMx, CMn = -CMz are body-axis moments and p, r body rates: no rotation
  CHECK(a.C_ell_beta == Approx(-0.071));
  CHECK(a.C_n_beta == Approx(0.084));
  CHECK(a.C_ell_p == Approx(-0.465));
  CHECK(a.C_n_r == Approx(-0.086));
  CHECK(a.C_n_delta_a == Approx(-0.0052));
  CHECK(a.C_Y_beta == Approx(-0.422));
  CHECK(a.C_D_p == Approx(0.028));
  CHECK(r.aircraft.e == Approx(0.85).epsilon(1e-6));
  CHECK(r.aircraft.rho == Approx(1.225));
  // what VSPAERO does not give is listed, what it gives is not
  CHECK(listed(r, "propulsion.*"));
  CHECK(listed(r, "aero.C_Y_0, C_ell_0, C_n_0"));
  CHECK_FALSE(listed(r, "aero.C_L_alpha"));
  CHECK_FALSE(listed(r, "aero.C_ell_delta_a"));
  CHECK_FALSE(listed(r, "aero.C_D_p"));
  CHECK_FALSE(listed(r, "environment.rho"));

  // the written file loads as sim_aero reads it, with the same numbers
  const auto path = temp_file("trainer.yaml");
  write_file(path, aero::aircraft_yaml(r.aircraft, {"test"}));
  const tern::Aircraft back = tern::load_aircraft(path.string());
  CHECK(back.aero.C_ell_p == Approx(a.C_ell_p));
  CHECK(back.aero.C_L_delta_e == Approx(a.C_L_delta_e));
  CHECK(back.mass == 4.5);
  std::filesystem::remove(path);
}

TEST_CASE("VSPAERO sweep in alpha: the point nearest zero angle of attack by default, another with --aoa") {
  // an alpha sweep as VSPAERO writes it, from AoA -10 deg: one block per point, C_ell_p tells them apart
  std::string text;
  for (double aoa : {-10.0, -5.0, 1.0, -1.0, 5.0})
    text += vspaero_stab(aoa, {}, "rad", {{"CL", {0.3 + 0.09 * aoa, 5.0}}, {"CMl", {0, 0, -0.05, -0.4 - 0.01 * aoa}}});
  const auto stab = temp_file("sweep.stab");
  write_file(stab, text);
  const auto t = aero::parse_vspaero_stab(stab.string());
  CHECK(t.alpha_ref == Approx(1.0 * kPi / 180.0));  // |1| = |-1|: the first of equals
  CHECK(t.d.at("C_ell_p") == Approx(-0.41));
  REQUIRE_FALSE(t.notes.empty());
  CHECK(t.notes[0].find("operating point: AoA_ 1 deg, Beta_ 0") != std::string::npos);
  CHECK(t.notes[0].find("nearest zero angle of attack of the 5 in the file (AoA_ -10 Beta_ 0, AoA_ -5") != std::string::npos);
  aero::VspaeroOptions o;
  o.aoa_deg = -10.0;
  const auto t10 = aero::parse_vspaero_stab(stab.string(), o);
  CHECK(t10.alpha_ref == Approx(-10.0 * kPi / 180.0));
  CHECK(t10.d.at("C_ell_p") == Approx(-0.3));
  CHECK(t10.notes[0].find("as --aoa asked") != std::string::npos);
  std::filesystem::remove(stab);
}

TEST_CASE("VSPAERO 2 layout ('# Coef Alpha ..', no CMl/CMn rows) reads as the VSPAERO 6/7 layout") {
  const auto v2 = aero::parse_vspaero_stab(kData + "/sample_vspaero_v2.stab");
  const auto v7 = aero::parse_vspaero_stab(kData + "/sample_vspaero.stab");
  CHECK(v2.S == v7.S);
  CHECK(v2.alpha_ref == Approx(v7.alpha_ref));
  CHECK(v2.rho == Approx(v7.rho));
  // C_ell = -CMx, C_n = -CMz, C_m = CMy; no control groups in VSPAERO 2
  int n = 0;
  for (const auto& [k, v] : v2.d) {
    CAPTURE(k);
    REQUIRE(v7.d.count(k));
    CHECK(v == Approx(v7.d.at(k)).epsilon(1e-9).scale(1.0));
    ++n;
  }
  CHECK(n == 18);  // C_L C_D C_m, 3 x (alpha, q), 3 x (beta, p, r)
  CHECK(v2.d.at("C_ell_beta") == Approx(-0.071));
  CHECK(v2.d.at("C_n_r") == Approx(-0.086));
  CHECK_FALSE(v2.d.count("C_m_delta_e"));
}

TEST_CASE("VSPAERO unit rows: control groups per deg are converted, per rad kept, anything else refused") {
  const double v = 0.0123;  // C_m per unit of the group's column
  const std::vector<std::string> g = {"Elevator"};
  const std::map<std::string, std::vector<double>> rows = {{"CL", {0.5, 5.0, 0, 0, 7, 0, 0, 0, 0.01}},
                                                           {"CMm", {0.0, -2.0, 0, 0, -30, 0, 0, 0, v}}};
  const auto p = temp_file("units.stab");
  write_file(p, vspaero_stab(2.0, g, "rad", rows));
  const double per_rad = aero::parse_vspaero_stab(p.string()).d.at("C_m_delta_e");
  write_file(p, vspaero_stab(2.0, g, "deg", rows));
  const double per_deg = aero::parse_vspaero_stab(p.string()).d.at("C_m_delta_e");
  CHECK(per_rad == Approx(v));
  CHECK(per_deg == Approx(v * 180.0 / kPi));
  write_file(p, vspaero_stab(2.0, g, "foo", rows));
  CHECK_THROWS_WITH_AS(aero::parse_vspaero_stab(p.string()),
                       doctest::Contains("unit of column ConGrp_1: 'per foo' (expected 'per rad' or 'per deg')"), std::runtime_error);
  std::filesystem::remove(p);
}

TEST_CASE("XFLR5 v6 analysis log: derived C_L and density, stability -> body axes, one control per polar") {
  const auto t = aero::parse_xflr5(kData + "/sample_xflr5.txt", "elevator");
  CHECK(t.S == Approx(0.52));
  CHECK(t.b == Approx(2.08));
  CHECK(t.c == Approx(0.235));
  CHECK(t.alpha_ref == Approx(2.0 * kPi / 180.0));  // "Alpha=2.00000°"
  // q S = -VInf Zw / CLa: C_L = m g/(q S), rho = 2 q S/(VInf^2 S) (XFLR5 prints neither)
  CHECK(t.d.at("C_L") == Approx(0.602).epsilon(1e-4));
  CHECK(t.rho == Approx(1.225).epsilon(1e-4));
  CHECK(t.d.at("C_m") == 0.0);
  CHECK(t.d.at("C_D") == Approx(0.029189 / 2).epsilon(1e-4));  // -Cxu/2, inviscid
  CHECK(t.d.at("C_L_delta_e") == Approx(0.1301));              // -CZde
  CHECK(t.d.at("C_D_delta_e") == Approx(0.0132));              // -CXde
  CHECK(t.d.at("C_m_delta_e") == Approx(-0.9912));             // CMde
  CHECK_FALSE(t.d.count("C_ell_delta_a"));
  // CLde of the aileron polar is the rolling moment, not lift
  const auto ta = aero::parse_xflr5(kData + "/sample_xflr5_aileron.txt", "aileron");
  CHECK(ta.d.at("C_ell_delta_a") == Approx(0.1702));
  CHECK(ta.d.at("C_Y_delta_a") == Approx(0.0602));
  CHECK(ta.d.at("C_n_delta_a") == Approx(-0.0052));
  CHECK_FALSE(ta.d.count("C_L_delta_e"));
  // without a control name the control derivatives are not read, and the notes say so
  const auto t0 = aero::parse_xflr5(kData + "/sample_xflr5.txt");
  CHECK_FALSE(t0.d.count("C_m_delta_e"));
  bool said = false;
  for (const auto& n : t0.notes) said = said || n.find("--xflr5-control") != std::string::npos;
  CHECK(said);

  auto tt = t;
  for (const auto& [k, v] : ta.d)
    if (k.find("_delta_a") != std::string::npos) tt.d[k] = v;
  const auto r = aero::build_aircraft(tt, {4.5, 0.24855, 0.3784, 0.618, 0.06}, nullptr, "trainer_x");
  const auto& a = r.aircraft.aero;
  const double c = std::cos(2.0 * kPi / 180), s = std::sin(2.0 * kPi / 180);
  // stability-axis rates and moments: C_l_p(body) = c^2 Clp - c s (Clr + Cnp) + s^2 Cnr
  CHECK(a.C_ell_p == Approx(c * c * -0.463 - c * s * (0.141 - 0.036) + s * s * -0.088));
  CHECK(a.C_n_r == Approx(s * s * -0.463 + c * s * (0.141 - 0.036) + c * c * -0.088));
  CHECK(a.C_Y_p == Approx(c * -0.031 - s * 0.218));
  CHECK(a.C_ell_delta_a == Approx(c * 0.1702 - s * -0.0052));
  CHECK(a.C_m_q == Approx(-30.54));
  CHECK(a.C_L_delta_e == Approx(0.1301));
  CHECK(a.C_D_alpha == Approx(t.d.at("C_L") - 0.2195));
  CHECK(a.C_m_0 == Approx(2.512 * 0.0349065850).epsilon(1e-8));  // Cm = 0 at the trimmed alpha
  CHECK(r.aircraft.rho == Approx(1.225).epsilon(1e-4));
  // no polar, inviscid C_D: Oswald e and C_D_p typical -- both listed; no rudder polar: listed
  CHECK(r.aircraft.e == 0.9);
  CHECK(a.C_D_p == 0.03);
  CHECK(listed(r, "wing.e"));
  CHECK(listed(r, "aero.C_D_p"));
  CHECK(listed(r, "aero.C_ell_delta_r"));
  CHECK_FALSE(listed(r, "aero.C_ell_p"));
  CHECK_FALSE(listed(r, "environment.rho"));

  // XFLR5's unit setting: lengths in cm, areas in dm²
  std::string text = read_file(kData + "/sample_xflr5.txt");
  const auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
  };
  replace("Ref. area  =     0.520 m\xC2\xB2", "Ref. area  =    52.000 dm\xC2\xB2");
  replace("Ref. span  =     2.080 m", "Ref. span  =   208.000 cm");
  const auto p = temp_file("xflr5_units.txt");
  write_file(p, text);
  const auto tu = aero::parse_xflr5(p.string());
  CHECK(tu.S == Approx(0.52));
  CHECK(tu.b == Approx(2.08));
  std::filesystem::remove(p);
}

TEST_CASE("round trip: the Anaconda -> VSPAERO-layout .stab (per-degree control groups) and .polar -> import") {
  const tern::Aircraft ac = tern::load_aircraft(kAircraft + "/anaconda.yaml");
  const auto& a = ac.aero;
  const double al = 3.0 * kPi / 180, d2r = kPi / 180;
  const double CL = a.C_L_0 + a.C_L_alpha * al, Cm = a.C_m_0 + a.C_m_alpha * al;
  const double CD = a.C_D_0 + a.C_D_alpha * al;
  // columns: Total Alpha Beta p q r Mach U, Elevator Aileron Rudder per degree; body axes as VSPAERO
  const std::map<std::string, std::vector<double>> rows = {
      {"CL", {CL, a.C_L_alpha, 0, 0, a.C_L_q, 0, 0, 0, a.C_L_delta_e * d2r, 0, 0}},
      {"CD", {CD, a.C_D_alpha, 0, 0, a.C_D_q, 0, 0, 0, a.C_D_delta_e * d2r, 0, 0}},
      {"CMm", {Cm, a.C_m_alpha, 0, 0, a.C_m_q, 0, 0, 0, a.C_m_delta_e * d2r, 0, 0}},
      {"CFy", {0, 0, a.C_Y_beta, a.C_Y_p, 0, a.C_Y_r, 0, 0, 0, a.C_Y_delta_a * d2r, a.C_Y_delta_r * d2r}},
      {"CMl", {0, 0, a.C_ell_beta, a.C_ell_p, 0, a.C_ell_r, 0, 0, 0, a.C_ell_delta_a * d2r, a.C_ell_delta_r * d2r}},
      {"CMn", {0, 0, a.C_n_beta, a.C_n_p, 0, a.C_n_r, 0, 0, 0, a.C_n_delta_a * d2r, a.C_n_delta_r * d2r}}};
  const auto stab = temp_file("rt.stab"), polar = temp_file("rt.polar");
  write_file(stab, vspaero_stab(3.0, {"Elevator", "Aileron", "Rudder"}, "deg", rows, ac.S, ac.c, ac.b, ac.rho));
  {
    std::ofstream p(polar);
    p << std::setprecision(12) << "      Beta Mach AoA Re/1e6 CL CDo CDi CDtot CS\n";
    for (double aoa : {-2.0, 0.0, 2.0, 4.0}) {
      const double cl = a.C_L_0 + a.C_L_alpha * aoa * d2r, cdi = cl * cl / (kPi * ac.e * ac.AR());
      p << "0 0.05 " << aoa << " 0.3 " << cl << " " << a.C_D_p << " " << cdi << " " << a.C_D_p + cdi << " 0\n";
    }
  }
  const auto t = aero::parse_vspaero_stab(stab.string());
  const aero::PolarFit pf = aero::parse_vspaero_polar(polar.string(), ac.AR());
  const auto r = aero::build_aircraft(t, {ac.mass, ac.Jx, ac.Jy, ac.Jz, ac.Jxz}, &pf, "rt");
  const auto& b = r.aircraft.aero;
  const std::pair<double, double> pairs[] = {{b.C_L_0, a.C_L_0},
                                             {b.C_L_alpha, a.C_L_alpha},
                                             {b.C_L_q, a.C_L_q},
                                             {b.C_L_delta_e, a.C_L_delta_e},
                                             {b.C_D_p, a.C_D_p},
                                             {b.C_D_0, a.C_D_0},
                                             {b.C_D_alpha, a.C_D_alpha},
                                             {b.C_D_delta_e, a.C_D_delta_e},
                                             {b.C_m_0, a.C_m_0},
                                             {b.C_m_alpha, a.C_m_alpha},
                                             {b.C_m_q, a.C_m_q},
                                             {b.C_m_delta_e, a.C_m_delta_e},
                                             {b.C_Y_beta, a.C_Y_beta},
                                             {b.C_Y_p, a.C_Y_p},
                                             {b.C_Y_r, a.C_Y_r},
                                             {b.C_Y_delta_a, a.C_Y_delta_a},
                                             {b.C_Y_delta_r, a.C_Y_delta_r},
                                             {b.C_ell_beta, a.C_ell_beta},
                                             {b.C_ell_p, a.C_ell_p},
                                             {b.C_ell_r, a.C_ell_r},
                                             {b.C_ell_delta_a, a.C_ell_delta_a},
                                             {b.C_ell_delta_r, a.C_ell_delta_r},
                                             {b.C_n_beta, a.C_n_beta},
                                             {b.C_n_p, a.C_n_p},
                                             {b.C_n_r, a.C_n_r},
                                             {b.C_n_delta_a, a.C_n_delta_a},
                                             {b.C_n_delta_r, a.C_n_delta_r}};
  int i = 0;
  for (const auto& [got, want] : pairs) {
    CAPTURE(i);
    CHECK(got == Approx(want).epsilon(1e-9).scale(1.0));
    ++i;
  }
  CHECK(r.aircraft.e == Approx(ac.e).epsilon(1e-9));
  CHECK(r.aircraft.rho == Approx(ac.rho));
  std::filesystem::remove(stab);
  std::filesystem::remove(polar);
}

TEST_CASE("malformed input: one line naming the file and field") {
  const std::string sample = read_file(kData + "/sample_vspaero.stab");
  const auto p = temp_file("bad.stab");
  auto check_one_line = [&](const std::string& text, const std::string& expect) {
    write_file(p, text);
    const std::string msg = error_of([&] { aero::parse_vspaero_stab(p.string()); });
    CAPTURE(msg);
    CHECK(msg.find(expect) != std::string::npos);
    CHECK(msg.rfind(p.string(), 0) == 0);        // starts with the file name
    CHECK(msg.find('\n') == std::string::npos);  // one line
  };
  auto edited = [&](const std::string& from, const std::string& to) {
    std::string s = sample;
    const auto at = s.find(from);
    REQUIRE(at != std::string::npos);
    return s.replace(at, from.size(), to);
  };
  check_one_line(edited("CMm       0.0872000   -2.5120000", "CMm       0.0872000          nan"),
                 ": CMm (line 51): 'nan' is not a finite number");
  check_one_line(edited("CL        0.6020000    5.2741000 ", "CL        0.6020000 "),
                 ": CL (line 47): expected 11 values (Total Alpha Beta p q r Mach U ConGrp_1 ConGrp_2 ConGrp_3), found 10");
  check_one_line(edited("#              -           rad          rad ", "#              -           rad          fathom "),
                 ": unit of column Beta: 'per fathom' (expected 'per rad' or 'per deg')");
  check_one_line(edited("Elevator               +0.100 deg          0.0169825 ", "Elevator               +0.100 deg "),
                 ": case list line 31: expected 'name delta units' and 12 coefficients");
  check_one_line("Sref_ 0.5 Lunit^2\nCref_ 0.2 Lunit\n",
                 ": derivative table: no 'Coef Total Alpha Beta p q r Mach U ...' column names found");
  CHECK_THROWS_WITH_AS(aero::parse_xflr5(kData + "/sample_vspaero.stab"), doctest::Contains(": CLa: missing"), std::runtime_error);
  // no regular file: nothing is read from it
  CHECK_THROWS_WITH_AS(aero::parse_vspaero_stab(kData), doctest::Contains((kData + ": file is a directory").c_str()), std::runtime_error);
  CHECK_THROWS_WITH_AS(aero::parse_xflr5("/dev/zero"), doctest::Contains("/dev/zero: file is not a regular file (a character device)"),
                       std::runtime_error);
  std::string polar = read_file(kData + "/sample_vspaero_v6.polar");
  polar += "0.0 0.05 9.0 0.27\n";
  write_file(p, polar);
  CHECK_THROWS_WITH_AS(aero::parse_vspaero_polar(p.string(), 8.32), doctest::Contains(": line 8: expected 23 columns, found 4"),
                       std::runtime_error);
  std::filesystem::remove(p);
}

TEST_CASE("linearize the Aerosonde at 25 m/s: trim-derived transfer functions and state-space entries") {
  const tern::Aircraft ac = tern::load_aircraft(kAircraft + "/aerosonde.yaml");
  sim::TrimRequest req;
  req.Va = 25.0;
  const aero::LinearModel lm = aero::linearize(ac, req);
  CHECK(lm.trim.alpha == Approx(0.0501).epsilon(1e-3));
  const double Va = 25.0, rho = ac.rho, S = ac.S, b = ac.b, c = ac.c;
  const double Gam = ac.Jx * ac.Jz - ac.Jxz * ac.Jxz;
  const double Cpp = (ac.Jz * ac.aero.C_ell_p + ac.Jxz * ac.aero.C_n_p) / Gam;
  const double Cpda = (ac.Jz * ac.aero.C_ell_delta_a + ac.Jxz * ac.aero.C_n_delta_a) / Gam;
  const double a_phi1 = -0.5 * rho * Va * Va * S * b * Cpp * b / (2 * Va);  // book eq. 5.26
  const double a_phi2 = 0.5 * rho * Va * Va * S * b * Cpda;
  const double a_theta1 = -rho * Va * Va * c * S / (2 * ac.Jy) * ac.aero.C_m_q * c / (2 * Va);
  const double a_theta3 = rho * Va * Va * c * S / (2 * ac.Jy) * ac.aero.C_m_delta_e;
  CHECK(lm.tf.at("a_phi1") == Approx(a_phi1));
  CHECK(lm.tf.at("a_phi2") == Approx(a_phi2));
  CHECK(lm.tf.at("a_theta1") == Approx(a_theta1));
  CHECK(lm.tf.at("a_theta3") == Approx(a_theta3));
  CHECK(a_phi1 == Approx(22.63).epsilon(1e-3));  // the book's Aerosonde numbers
  CHECK(a_phi2 == Approx(130.88).epsilon(1e-3));
  CHECK(lm.tf.at("a_V3") == Approx(9.81).epsilon(1e-6));
  // the numerical A, B (central differences of the nonlinear model) hold the same entries:
  // L_p = -a_phi1 at q = 0 (book table 5.1), L_delta_a = a_phi2, M_q = -a_theta1, M_delta_e = a_theta3
  CHECK(lm.A_lat(1, 1) == Approx(-a_phi1).epsilon(1e-5));
  CHECK(lm.B_lat(1, 0) == Approx(a_phi2).epsilon(1e-5));
  CHECK(lm.A_lon(2, 2) == Approx(-a_theta1).epsilon(1e-5));
  CHECK(lm.B_lon(2, 0) == Approx(a_theta3).epsilon(1e-5));
  // kinematics: theta' = q, h' = Va theta (level trim, book eq. 5.50), psi' = r / cos(theta)
  CHECK(lm.A_lon(3, 2) == Approx(1.0));
  CHECK(lm.A_lon(4, 3) == Approx(Va).epsilon(1e-4));
  CHECK(lm.A_lat(4, 2) == Approx(1.0 / std::cos(lm.trim.theta)));
  // X_delta_t = a_V2 (thrust per throttle / m at alpha ~ 0 contributes cos(alpha))
  CHECK(lm.B_lon(0, 1) == Approx(lm.tf.at("a_V2")).epsilon(1e-6));
  // dynamic modes of the trimmed Aerosonde are stable (all eigenvalues of the u w q theta block)
  const Eigen::Matrix4d Al = lm.A_lon.topLeftCorner<4, 4>();
  for (const auto& ev : Al.eigenvalues()) CHECK(ev.real() < 0.0);
}

TEST_CASE("gains for the Anaconda at 17 m/s reproduce configs/gains/anaconda.yaml's designed values") {
  const tern::Aircraft ac = tern::load_aircraft(kAircraft + "/anaconda.yaml");
  sim::TrimRequest req;
  req.Va = 17.0;
  const auto g = aero::design_gains(aero::linearize(ac, req), aero::DesignOptions{});
  const YAML::Node file = YAML::LoadFile(kAircraft + "/../gains/anaconda.yaml");
  REQUIRE(g.size() == 21);
  for (const auto& [name, value] : g) {
    CAPTURE(name);
    REQUIRE(file[name]);
    CHECK(value == Approx(file[name].as<double>()).epsilon(1e-4).scale(1e-6));
  }
  // a different choice moves the right gain: a faster roll loop adds rate feedback
  aero::DesignOptions fast;
  fast.wn_phi = 25.0;
  const auto g2 = aero::design_gains(aero::linearize(ac, req), fast);
  CHECK(g2[1].first == "roll_kd");
  CHECK(g2[4].first == "roll_rate_max");
  CHECK(g2[1].second > 0.05);
}

TEST_CASE("modes of the Aerosonde at 25 m/s: eigenvalues against the textbook approximations") {
  const tern::Aircraft ac = tern::load_aircraft(kAircraft + "/aerosonde.yaml");
  sim::TrimRequest req;
  req.Va = 25.0;
  const aero::LinearModel lm = aero::linearize(ac, req);
  const aero::Modes m = aero::dynamic_modes(lm);
  const aero::ModeApproximations ap = aero::approximate_modes(ac, lm);
  CAPTURE(aero::modes_table(m, ap));
  CHECK(m.notes.empty());  // the modes separate in frequency as the eigenvectors say
  const aero::Mode* sp = aero::find_mode(m, "short period");
  const aero::Mode* ph = aero::find_mode(m, "phugoid");
  const aero::Mode* roll = aero::find_mode(m, "roll");
  const aero::Mode* spiral = aero::find_mode(m, "spiral");
  const aero::Mode* dr = aero::find_mode(m, "dutch roll");
  REQUIRE(sp);
  REQUIRE(ph);
  REQUIRE(roll);
  REQUIRE(spiral);
  REQUIRE(dr);
  CHECK(sp->oscillatory);
  CHECK(ph->oscillatory);
  CHECK(dr->oscillatory);
  CHECK_FALSE(roll->oscillatory);
  CHECK_FALSE(spiral->oscillatory);
  // Tolerances: what each approximation neglects (measured differences in brackets). Short period
  // (alpha, q only: the speed change) [1.0 %, 1.2 %]; phugoid (Lanchester: alpha and pitch
  // dynamics, the variation of thrust with speed) [11 %, 5.5 %]; roll (roll alone: sideslip and
  // yaw coupling) [0.8 %]; spiral (quasi-steady roll and yaw) [9 %]; dutch roll (beta, r only:
  // the roll coupling) [5.5 %, 7.5 %].
  CHECK(sp->wn == Approx(ap.short_period_wn).epsilon(0.03));
  CHECK(sp->zeta == Approx(ap.short_period_zeta).epsilon(0.05));
  CHECK(ph->wn == Approx(ap.phugoid_wn).epsilon(0.15));
  CHECK(ph->zeta == Approx(ap.phugoid_zeta).epsilon(0.10));
  CHECK(roll->lambda.real() == Approx(ap.roll_lambda).epsilon(0.02));
  CHECK(spiral->lambda.real() == Approx(ap.spiral_lambda).epsilon(0.15));
  CHECK(dr->wn == Approx(ap.dutch_roll_wn).epsilon(0.10));
  CHECK(dr->zeta == Approx(ap.dutch_roll_zeta).epsilon(0.12));
  // the book's Aerosonde: a divergent spiral doubling in about 8 s, the other modes stable
  CHECK_FALSE(spiral->stable);
  CHECK(spiral->t_double == Approx(7.75).epsilon(0.01));
  for (const aero::Mode* x : {sp, ph, roll, dr}) CHECK(x->stable);
  // the figures of a mode follow from its eigenvalue
  CHECK(sp->zeta == Approx(-sp->lambda.real() / std::abs(sp->lambda)));
  CHECK(sp->period == Approx(2 * kPi / sp->lambda.imag()));
  CHECK(roll->tau == Approx(-1.0 / roll->lambda.real()));
  // the eigenvalues are those of the whole 5x5 blocks (plus the h and psi integrators at zero)
  Eigen::EigenSolver<Eigen::Matrix<double, 5, 5>> es(lm.A_lat);
  int matched = 0;
  for (const auto& ev : es.eigenvalues())
    for (const aero::Mode* x : {roll, spiral, dr})
      if (std::abs(ev - x->lambda) < 1e-6 || std::abs(ev - std::conj(x->lambda)) < 1e-6) ++matched;
  CHECK(matched == 4);
}

TEST_CASE("modes are told apart by eigenvector content, not only by frequency; figures of unstable roots") {
  aero::LinearModel lm;
  lm.Va = 20.0;
  lm.A_lon.setZero();
  lm.A_lat.setZero();
  // longitudinal [u w q theta]: an (alpha, q) oscillation at 0.5 rad/s and a (u, theta) one at 3 rad/s:
  // the first is the short period by content although it is the slower
  lm.A_lon.block<2, 2>(1, 1) << -0.2, 20.0, -0.0125, 0.0;  // w, q: lambda^2 + 0.2 lambda + 0.25
  lm.A_lon(0, 0) = -1.0;                                   // u, theta: lambda^2 + lambda + 9
  lm.A_lon(0, 3) = -9.0;
  lm.A_lon(3, 0) = 1.0;
  // lateral [v p r phi]: a (v, r) oscillation, p' = -8 p, phi' = p + 0.05 phi (a divergent spiral)
  lm.A_lat(0, 0) = -0.5;
  lm.A_lat(0, 2) = -20.0;
  lm.A_lat(2, 0) = 0.5;
  lm.A_lat(2, 2) = -0.3;
  lm.A_lat(1, 1) = -8.0;
  lm.A_lat(3, 1) = 1.0;
  lm.A_lat(3, 3) = 0.05;
  const aero::Modes m = aero::dynamic_modes(lm);
  const aero::Mode* sp = aero::find_mode(m, "short period");
  const aero::Mode* ph = aero::find_mode(m, "phugoid");
  REQUIRE(sp);
  REQUIRE(ph);
  CHECK(sp->wn == Approx(0.5));
  CHECK(sp->zeta == Approx(0.2));
  CHECK(ph->wn == Approx(3.0));
  REQUIRE(m.notes.size() == 1);
  CHECK(m.notes[0].find("overlap in frequency") != std::string::npos);
  const aero::Mode* roll = aero::find_mode(m, "roll");
  const aero::Mode* spiral = aero::find_mode(m, "spiral");
  const aero::Mode* dr = aero::find_mode(m, "dutch roll");
  REQUIRE(roll);
  REQUIRE(spiral);
  REQUIRE(dr);
  CHECK(roll->lambda.real() == Approx(-8.0));
  CHECK(roll->tau == Approx(0.125));
  CHECK(roll->stable);
  CHECK(spiral->lambda.real() == Approx(0.05));
  CHECK_FALSE(spiral->stable);
  CHECK(spiral->t_double == Approx(std::log(2.0) / 0.05));
  CHECK(spiral->tau == 0.0);
  CHECK(dr->wn == Approx(std::sqrt(0.15 + 10.0)));  // lambda^2 + 0.8 lambda + (0.15 + 10)
  const std::string table = aero::modes_table(m, aero::ModeApproximations{});
  CHECK(table.find("spiral") != std::string::npos);
  CHECK(table.find("NO") != std::string::npos);
  // an overdamped short period: two real roots, both named
  lm.A_lon.block<2, 2>(1, 1) << -5.0, 20.0, 0.0, -4.0;
  const aero::Modes m2 = aero::dynamic_modes(lm);
  CHECK(aero::find_mode(m2, "short period (real, fast)"));
  CHECK(aero::find_mode(m2, "short period (real, slow)"));
}
