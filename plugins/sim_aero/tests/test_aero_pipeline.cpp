// Tests of the modelling pipeline of `tern aero import|linearize|gains` (issue 11).
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <unistd.h>

#include <Eigen/Eigenvalues>
#include <yaml-cpp/yaml.h>

#include "aero_pipeline.hpp"
#include "tern_sim_aero/aircraft.hpp"

namespace sim = tern::sim;
namespace aero = tern::aero;
using doctest::Approx;

namespace {

const std::string kData = TERN_SIM_AERO_TEST_DATA;
const std::string kAircraft = TERN_AIRCRAFT_DIR;
constexpr double kPi = 3.14159265358979323846;

bool listed(const aero::ImportResult& r, const std::string& name) {
  for (const auto& d : r.defaults)
    if (d.name == name) return true;
  return false;
}

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("tern_aero_test_" + std::to_string(::getpid()) + "_" + name);
}

}  // namespace

TEST_CASE("VSPAERO .stab + .polar import: per-degree columns, stability -> body axes, drag fit") {
  const auto t = aero::parse_vspaero_stab(kData + "/sample_vspaero.stab");
  CHECK(t.S == Approx(0.52));
  CHECK(t.b == Approx(2.08));
  CHECK(t.c == Approx(0.235));
  CHECK(t.alpha_ref == Approx(2.0 * kPi / 180.0));
  CHECK(t.rho == Approx(1.225));
  // control groups are "per deg" in the sample: 0.00227 / deg = 0.00227 * 57.29578 / rad
  CHECK(t.d.at("C_L_delta_e") == Approx(0.00227 * 57.2957795).epsilon(1e-8));
  CHECK(t.d.at("C_m_delta_e") == Approx(-0.0173 * 57.2957795).epsilon(1e-8));
  CHECK(t.d.at("C_ell_delta_a") == Approx(0.00297 * 57.2957795).epsilon(1e-8));
  CHECK(t.d.at("C_L_alpha") == Approx(5.2741));  // "per rad" stays

  const aero::PolarFit pf = aero::parse_vspaero_polar(kData + "/sample_vspaero.polar", 2.08 * 2.08 / 0.52);
  CHECK(pf.rows == 6);
  CHECK(pf.C_D_p == Approx(0.028));
  CHECK(pf.e == Approx(0.85).epsilon(1e-4));

  const aero::MassProperties m = aero::load_mass_file(kData + "/sample_mass.yaml");
  CHECK(m.mass == 4.5);
  CHECK(m.Jxz == 0.06);
  const auto r = aero::build_aircraft(t, m, &pf, "trainer");
  const auto& a = r.aircraft.aero;
  const double ca = std::cos(2.0 * kPi / 180), sa = std::sin(2.0 * kPi / 180);
  CHECK(a.C_L_0 == Approx(0.602 - 5.2741 * 0.0349065850).epsilon(1e-8));
  CHECK(a.C_m_0 == Approx(0.0872 + 2.512 * 0.0349065850).epsilon(1e-8));
  // moments about the stability axes rotated to body axes: l_b = c l_s - s n_s, n_b = s l_s + c n_s
  CHECK(a.C_ell_beta == Approx(ca * -0.068 - sa * 0.0865));
  CHECK(a.C_n_beta == Approx(sa * -0.068 + ca * 0.0865));
  // VSPAERO's rates are body rates: only the moment rows rotate
  CHECK(a.C_ell_p == Approx(ca * -0.463 - sa * -0.036));
  CHECK(a.C_n_r == Approx(sa * 0.141 + ca * -0.088));
  CHECK(a.C_Y_beta == Approx(-0.422));
  CHECK(a.C_D_p == Approx(0.028));
  CHECK(r.aircraft.e == Approx(0.85).epsilon(1e-4));
  CHECK(r.aircraft.rho == Approx(1.225));
  // what VSPAERO does not give is listed, what it gives is not
  CHECK(listed(r, "propulsion.*"));
  CHECK(listed(r, "aero.C_Y_0, C_ell_0, C_n_0"));
  CHECK_FALSE(listed(r, "aero.C_L_alpha"));
  CHECK_FALSE(listed(r, "aero.C_D_p"));
  CHECK_FALSE(listed(r, "environment.rho"));

  // the written file loads as sim_aero reads it, with the same numbers
  const auto path = temp_file("trainer.yaml");
  {
    std::ofstream f(path);
    f << aero::aircraft_yaml(r.aircraft, {"test"});
  }
  const sim::Aircraft back = sim::load_aircraft(path.string());
  CHECK(back.aero.C_ell_p == Approx(a.C_ell_p));
  CHECK(back.aero.C_L_delta_e == Approx(a.C_L_delta_e));
  CHECK(back.mass == 4.5);
  std::filesystem::remove(path);
}

TEST_CASE("XFLR5 import: stability-axis rate derivatives rotated to body axes, C_D_alpha from Cxa") {
  const auto t = aero::parse_xflr5(kData + "/sample_xflr5.txt");
  CHECK(t.S == Approx(0.52));
  CHECK(t.b == Approx(2.08));
  CHECK(t.c == Approx(0.235));
  CHECK(t.rho == Approx(1.225));
  CHECK(t.alpha_ref == Approx(2.0 * kPi / 180.0));  // "Alpha = 2.000 deg"
  const auto r = aero::build_aircraft(t, {4.5, 0.24855, 0.3784, 0.618, 0.06}, nullptr, "trainer_x");
  const auto& a = r.aircraft.aero;
  const double c = std::cos(2.0 * kPi / 180), s = std::sin(2.0 * kPi / 180);
  // rates in stability axes too: C_l_p(body) = c^2 Clp - c s (Clr + Cnp) + s^2 Cnr
  CHECK(a.C_ell_p == Approx(c * c * -0.463 - c * s * (0.141 - 0.036) + s * s * -0.088));
  CHECK(a.C_n_r == Approx(s * s * -0.463 + c * s * (0.141 - 0.036) + c * c * -0.088));
  CHECK(a.C_Y_p == Approx(c * -0.031 - s * 0.218));
  CHECK(a.C_ell_delta_a == Approx(c * 0.1702 - s * -0.0052));
  CHECK(a.C_m_q == Approx(-30.54));
  CHECK(a.C_L_delta_e == Approx(0.1301));
  CHECK(a.C_D_alpha == Approx(0.602 - 0.2195));
  CHECK(a.C_m_0 == Approx(2.512 * 0.0349065850).epsilon(1e-8));  // Cm = 0 at the trimmed alpha
  // no polar: Oswald e typical, C_D_p = C_D - C_L^2/(pi e AR) -- both listed
  CHECK(r.aircraft.e == 0.9);
  CHECK(a.C_D_p == Approx(0.038 - 0.602 * 0.602 / (kPi * 0.9 * 2.08 * 2.08 / 0.52)));
  CHECK(listed(r, "wing.e"));
  CHECK(listed(r, "aero.C_D_p"));
  CHECK(listed(r, "aero.C_D_q"));
  CHECK_FALSE(listed(r, "aero.C_ell_p"));
}

TEST_CASE("round trip: the Anaconda -> synthetic VSPAERO .stab/.polar (per-degree controls) -> import") {
  const sim::Aircraft ac = sim::load_aircraft(kAircraft + "/anaconda.yaml");
  const auto& a = ac.aero;
  const double al = 3.0 * kPi / 180, c = std::cos(al), s = std::sin(al), d2r = kPi / 180;
  // body -> stability axes: [l; n]_s = T [l; n]_b (body rates, as VSPAERO)
  auto ls = [&](double l, double n) { return c * l + s * n; };
  auto ns = [&](double l, double n) { return -s * l + c * n; };
  const double CL = a.C_L_0 + a.C_L_alpha * al, Cm = a.C_m_0 + a.C_m_alpha * al;
  const double CD = a.C_D_0 + a.C_D_alpha * al;
  std::ostringstream o;
  o << std::setprecision(12);
  o << "Sref_ " << ac.S << " Lunit^2\nCref_ " << ac.c << " Lunit\nBref_ " << ac.b << " Lunit\nAoA_ 3.0 deg\nRho_ "
    << ac.rho << " x\n"
    << "# Coef Total Alpha Beta p q r Mach U ConGrp_1 ConGrp_2 ConGrp_3\n"
    << "#  -  per rad per rad per rad per rad per rad per M per u per deg per deg per deg\n";
  auto row = [&](const char* n, double tot, double al_, double be, double p, double q, double r, double de, double da,
                 double dr) {
    o << n << " " << tot << " " << al_ << " " << be << " " << p << " " << q << " " << r << " 0 0 " << de * d2r << " "
      << da * d2r << " " << dr * d2r << "\n";
  };
  row("CL", CL, a.C_L_alpha, 0, 0, a.C_L_q, 0, a.C_L_delta_e, 0, 0);
  row("CD", CD, a.C_D_alpha, 0, 0, a.C_D_q, 0, a.C_D_delta_e, 0, 0);
  row("CMm", Cm, a.C_m_alpha, 0, 0, a.C_m_q, 0, a.C_m_delta_e, 0, 0);
  row("CFy", 0, 0, a.C_Y_beta, a.C_Y_p, 0, a.C_Y_r, 0, a.C_Y_delta_a, a.C_Y_delta_r);
  row("CMl", 0, 0, ls(a.C_ell_beta, a.C_n_beta), ls(a.C_ell_p, a.C_n_p), 0, ls(a.C_ell_r, a.C_n_r), 0,
      ls(a.C_ell_delta_a, a.C_n_delta_a), ls(a.C_ell_delta_r, a.C_n_delta_r));
  row("CMn", 0, 0, ns(a.C_ell_beta, a.C_n_beta), ns(a.C_ell_p, a.C_n_p), 0, ns(a.C_ell_r, a.C_n_r), 0,
      ns(a.C_ell_delta_a, a.C_n_delta_a), ns(a.C_ell_delta_r, a.C_n_delta_r));
  const auto stab = temp_file("rt.stab"), polar = temp_file("rt.polar");
  {
    std::ofstream f(stab);
    f << o.str();
    std::ofstream p(polar);
    p << std::setprecision(12) << "Beta Mach AoA CL CDo CDi\n";
    for (double aoa : {-2.0, 0.0, 2.0, 4.0}) {
      const double cl = a.C_L_0 + a.C_L_alpha * aoa * d2r;
      p << "0 0.05 " << aoa << " " << cl << " " << a.C_D_p << " " << cl * cl / (kPi * ac.e * ac.AR()) << "\n";
    }
  }
  const auto t = aero::parse_vspaero_stab(stab.string());
  const aero::PolarFit pf = aero::parse_vspaero_polar(polar.string(), ac.AR());
  const auto r = aero::build_aircraft(t, {ac.mass, ac.Jx, ac.Jy, ac.Jz, ac.Jxz}, &pf, "rt");
  const auto& b = r.aircraft.aero;
  const std::pair<double, double> pairs[] = {
      {b.C_L_0, a.C_L_0}, {b.C_L_alpha, a.C_L_alpha}, {b.C_L_q, a.C_L_q}, {b.C_L_delta_e, a.C_L_delta_e},
      {b.C_D_p, a.C_D_p}, {b.C_D_0, a.C_D_0}, {b.C_D_alpha, a.C_D_alpha}, {b.C_D_delta_e, a.C_D_delta_e},
      {b.C_m_0, a.C_m_0}, {b.C_m_alpha, a.C_m_alpha}, {b.C_m_q, a.C_m_q}, {b.C_m_delta_e, a.C_m_delta_e},
      {b.C_Y_beta, a.C_Y_beta}, {b.C_Y_p, a.C_Y_p}, {b.C_Y_r, a.C_Y_r}, {b.C_Y_delta_a, a.C_Y_delta_a},
      {b.C_Y_delta_r, a.C_Y_delta_r}, {b.C_ell_beta, a.C_ell_beta}, {b.C_ell_p, a.C_ell_p}, {b.C_ell_r, a.C_ell_r},
      {b.C_ell_delta_a, a.C_ell_delta_a}, {b.C_ell_delta_r, a.C_ell_delta_r}, {b.C_n_beta, a.C_n_beta},
      {b.C_n_p, a.C_n_p}, {b.C_n_r, a.C_n_r}, {b.C_n_delta_a, a.C_n_delta_a}, {b.C_n_delta_r, a.C_n_delta_r}};
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

TEST_CASE("bad input: one line naming the file and field") {
  const auto p = temp_file("bad.stab");
  {
    std::ofstream f(p);
    f << "Sref_ 0.5 x\nCref_ 0.2 x\n# Coef Total Alpha\n#  -  per rad\nCL 0.5 nan\n";
  }
  CHECK_THROWS_WITH_AS(aero::parse_vspaero_stab(p.string()),
                       doctest::Contains("CL: 'nan' is not a finite number"), std::runtime_error);
  {
    std::ofstream f(p);
    f << "Sref_ 0.5 x\n";
  }
  CHECK_THROWS_WITH_AS(aero::parse_vspaero_stab(p.string()), doctest::Contains("no '# Coef"), std::runtime_error);
  CHECK_THROWS_WITH_AS(aero::parse_xflr5(kData + "/sample_vspaero.stab"), doctest::Contains("CLa: missing"),
                       std::runtime_error);
  std::filesystem::remove(p);
}

TEST_CASE("linearize the Aerosonde at 25 m/s: trim-derived transfer functions and state-space entries") {
  const sim::Aircraft ac = sim::load_aircraft(kAircraft + "/aerosonde.yaml");
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
  const sim::Aircraft ac = sim::load_aircraft(kAircraft + "/anaconda.yaml");
  sim::TrimRequest req;
  req.Va = 17.0;
  const auto g = aero::design_gains(aero::linearize(ac, req), aero::DesignOptions{});
  const YAML::Node file = YAML::LoadFile(kAircraft + "/../gains/anaconda.yaml");
  REQUIRE(g.size() == 19);
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
  CHECK(g2[1].second > 0.05);
}
