// modes.cpp: see tern/aero/modes.hpp.
#include "tern/aero/modes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "tern/math.hpp"
#include "tern/aero/model.hpp"

namespace tern::aero {
namespace {

using cd = std::complex<double>;

// One eigenvalue with its eigenvector's content score (see identify()).
struct Root {
  cd lambda;
  double score = 0;
};

// A mode candidate: one real root or a complex pair (stored once, imag > 0).
struct Group {
  std::vector<Root> roots;  // 1 (real) or 2 (pair: lambda and its conjugate)
  double score() const {
    double s = 0;
    for (const auto& r : roots) s += r.score;
    return s;
  }
  double speed() const { return std::abs(roots[0].lambda); }
};

// Eigenvalues of a 4x4 block and, per eigenvalue, a / (a + b) of the magnitudes of the
// eigenvector's components ia and ib (the content score), grouped into pairs and real roots.
std::vector<Group> eigen_groups(const Eigen::Matrix4d& A, int ia, int ib, double scale_a, double scale_b) {
  Eigen::EigenSolver<Eigen::Matrix4d> es(A, true);
  if (es.info() != Eigen::Success) throw std::runtime_error("linearize: modes: the eigenvalue solver did not converge");
  const auto ev = es.eigenvalues();
  const auto V = es.eigenvectors();
  std::vector<Group> groups;
  for (int k = 0; k < 4; ++k) {
    const cd l = ev(k);
    const double a = std::abs(V(ia, k)) * scale_a, b = std::abs(V(ib, k)) * scale_b;
    const double score = a + b > 0 ? a / (a + b) : 0.0;
    const double tol = 1e-9 * std::max(1.0, std::abs(l));
    if (std::abs(l.imag()) <= tol) {
      groups.push_back({{{cd(l.real(), 0.0), score}}});
    } else if (l.imag() > 0) {  // Eigen lists a pair next to each other; keep it once
      groups.push_back({{{l, score}, {std::conj(l), score}}});
    }
  }
  return groups;
}

Mode make_mode(const std::string& name, cd l) {
  Mode m;
  m.name = name;
  m.lambda = l;
  m.oscillatory = l.imag() != 0.0;
  m.stable = l.real() < 0.0;
  m.wn = std::abs(l);
  m.zeta = m.wn > 0 ? -l.real() / m.wn : 0.0;
  if (m.oscillatory) m.period = 2.0 * kPi / l.imag();
  if (l.real() < 0) m.tau = -1.0 / l.real();
  if (l.real() > 0) m.t_double = std::log(2.0) / l.real();
  return m;
}

// Splits the groups into the two eigenvalues of highest content score (first) and the rest.
void split_by_score(const std::vector<Group>& g, std::vector<Group>& hi, std::vector<Group>& lo) {
  const int n = static_cast<int>(g.size());
  int best = -1;
  double best_score = -1;
  for (int mask = 0; mask < (1 << n); ++mask) {
    int count = 0;
    double s = 0;
    for (int i = 0; i < n; ++i)
      if (mask & (1 << i)) count += static_cast<int>(g[i].roots.size()), s += g[i].score();
    if (count == 2 && s > best_score) best = mask, best_score = s;
  }
  for (int i = 0; i < n; ++i) ((best & (1 << i)) ? hi : lo).push_back(g[i]);
}

// Modes of one pair of eigenvalues (a complex pair or two real roots, fastest first).
void add_modes(std::vector<Mode>& out, const std::vector<Group>& g, const std::string& name) {
  if (g.size() == 1) {
    out.push_back(make_mode(name, g[0].roots[0].lambda));
    return;
  }
  std::vector<cd> r = {g[0].roots[0].lambda, g[1].roots[0].lambda};
  std::sort(r.begin(), r.end(), [](cd a, cd b) { return std::abs(a) > std::abs(b); });
  out.push_back(make_mode(name + " (real, fast)", r[0]));
  out.push_back(make_mode(name + " (real, slow)", r[1]));
}

double slowest(const std::vector<Group>& g) {
  double s = std::numeric_limits<double>::infinity();
  for (const auto& x : g) s = std::min(s, x.speed());
  return s;
}
double fastest(const std::vector<Group>& g) {
  double s = 0;
  for (const auto& x : g) s = std::max(s, x.speed());
  return s;
}

}  // namespace

Modes dynamic_modes(const LinearModel& lm) {
  Modes m;
  const double Va = lm.Va;
  // longitudinal [u w q theta]: short period = most alpha (w/Va) against u/Va
  const Eigen::Matrix4d Alon = lm.A_lon.topLeftCorner<4, 4>();
  std::vector<Group> sp, ph;
  split_by_score(eigen_groups(Alon, 1, 0, 1.0 / Va, 1.0 / Va), sp, ph);
  add_modes(m.lon, sp, "short period");
  add_modes(m.lon, ph, "phugoid");
  if (slowest(sp) < fastest(ph))
    m.notes.push_back("short period and phugoid overlap in frequency: told apart by eigenvector content (alpha vs u)");
  // lateral [v p r phi]: dutch roll = most sideslip (v/Va) against phi
  const Eigen::Matrix4d Alat = lm.A_lat.topLeftCorner<4, 4>();
  std::vector<Group> dr, rs;
  split_by_score(eigen_groups(Alat, 0, 3, 1.0 / Va, 1.0), dr, rs);
  if (rs.size() == 1) {
    m.lat.push_back(make_mode("roll-spiral", rs[0].roots[0].lambda));
    m.notes.push_back("roll and spiral roots form one oscillation (the lateral phugoid)");
  } else {
    const bool first_fast = rs[0].speed() >= rs[1].speed();
    m.lat.push_back(make_mode("roll", rs[first_fast ? 0 : 1].roots[0].lambda));
    m.lat.push_back(make_mode("spiral", rs[first_fast ? 1 : 0].roots[0].lambda));
  }
  add_modes(m.lat, dr, "dutch roll");
  if (rs.size() == 2 && slowest(dr) < slowest(rs))
    m.notes.push_back("dutch roll slower than the spiral: told apart by eigenvector content (beta vs phi)");
  return m;
}

ModeApproximations approximate_modes(const tern::Aircraft& ac, const LinearModel& lm) {
  const auto& a = ac.aero;
  const auto& k = lm.tf;
  const double Va = lm.Va, m = ac.mass, S = ac.S, b = ac.b, g = tern::kGravity;
  const double qS = 0.5 * ac.rho * Va * Va * S;
  const double alpha = lm.trim.alpha;
  ModeApproximations o;
  // short period
  const double Z_alpha = -qS * (a.C_L_alpha + sim::drag_coefficient(ac, alpha)) / m;
  const double M_alpha = -k.at("a_theta2"), M_q = -k.at("a_theta1");
  o.short_period_wn = std::sqrt(std::max(0.0, Z_alpha * M_q / Va - M_alpha));
  o.short_period_zeta = -(Z_alpha / Va + M_q) / (2.0 * o.short_period_wn);
  // phugoid
  const double C_L = sim::lift_coefficient(ac, alpha) + a.C_L_delta_e * lm.trim.delta.delta_e;
  const double Z_u = -2.0 * qS * C_L / (m * Va);
  o.phugoid_wn = std::sqrt(std::max(0.0, -Z_u * g / Va));
  o.phugoid_zeta = k.at("a_V1") / (2.0 * o.phugoid_wn);
  // lateral: book table 5.2's moment derivatives (Gamma form), per rad of beta and per rad/s
  const double Gam = ac.Jx * ac.Jz - ac.Jxz * ac.Jxz;
  const double G3 = ac.Jz / Gam, G4 = ac.Jxz / Gam, G8 = ac.Jx / Gam;
  auto Cp = [&](double ell, double n) { return G3 * ell + G4 * n; };
  auto Cr = [&](double ell, double n) { return G4 * ell + G8 * n; };
  const double qSb = qS * b, rate = b / (2.0 * Va);
  const double L_beta = qSb * Cp(a.C_ell_beta, a.C_n_beta), N_beta = qSb * Cr(a.C_ell_beta, a.C_n_beta);
  const double L_p = qSb * rate * Cp(a.C_ell_p, a.C_n_p), N_p = qSb * rate * Cr(a.C_ell_p, a.C_n_p);
  const double L_r = qSb * rate * Cp(a.C_ell_r, a.C_n_r), N_r = qSb * rate * Cr(a.C_ell_r, a.C_n_r);
  o.roll_lambda = L_p;
  o.spiral_lambda = -(g / Va) * (L_beta * N_r - L_r * N_beta) / (L_beta * N_p - L_p * N_beta);
  const double Y_beta = qS * a.C_Y_beta / m;
  o.dutch_roll_wn = std::sqrt(std::max(0.0, N_beta + Y_beta * N_r / Va));
  o.dutch_roll_zeta = -(Y_beta / Va + N_r) / (2.0 * o.dutch_roll_wn);
  return o;
}

namespace {

std::string format(const char* f, double a, double b = 0) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, a, b);
  return buf;
}

std::string table_row(const Mode& m) {
  char buf[200];
  const std::string ev = m.oscillatory ? format("%+.4f +- %.4fj", m.lambda.real(), m.lambda.imag()) : format("%+.4f", m.lambda.real());
  const std::string dash = "-";
  std::snprintf(buf, sizeof buf, "#   %-24s %-24s %9.4f %7s %9s %9s %9s  %s\n", m.name.c_str(), ev.c_str(), m.wn,
                m.oscillatory ? format("%.3f", m.zeta).c_str() : dash.c_str(),
                m.oscillatory ? format("%.3f", m.period).c_str() : dash.c_str(), m.tau > 0 ? format("%.3f", m.tau).c_str() : dash.c_str(),
                m.t_double > 0 ? format("%.3f", m.t_double).c_str() : dash.c_str(),
                m.stable ? "yes" : (m.lambda.real() == 0.0 ? "neutral" : "NO"));
  return buf;
}

}  // namespace

std::string modes_table(const Modes& modes, const ModeApproximations& a) {
  char head[200];
  std::snprintf(head, sizeof head, "#   %-24s %-24s %9s %7s %9s %9s %9s  %s\n", "mode", "eigenvalue 1/s", "wn rad/s", "zeta", "period s",
                "tau s", "T2 s", "stable");
  std::string s =
      "# dynamic modes: eigenvalues of A_lon's [u w q theta] and A_lat's [v p r phi] (h and psi are\n"
      "# integrators); tau = -1/Re (time constant), T2 = ln 2/Re (time to double, unstable)\n";
  s += head;
  for (const auto* v : {&modes.lon, &modes.lat})
    for (const auto& m : *v) s += table_row(m);
  for (const auto& n : modes.notes) s += "#   note: " + n + "\n";
  s += "# textbook approximations from the coefficients (modes.hpp), to compare:\n#   short period wn " +
       format("%.3f rad/s zeta %.3f", a.short_period_wn, a.short_period_zeta) + ", phugoid wn " +
       format("%.3f rad/s zeta %.3f", a.phugoid_wn, a.phugoid_zeta) + ",\n#   roll " + format("%+.4f 1/s", a.roll_lambda) + ", spiral " +
       format("%+.4f 1/s", a.spiral_lambda) + ", dutch roll wn " + format("%.3f rad/s zeta %.3f", a.dutch_roll_wn, a.dutch_roll_zeta) +
       "\n";
  return s;
}

const Mode* find_mode(const Modes& modes, const std::string& name) {
  for (const auto* v : {&modes.lon, &modes.lat})
    for (const auto& m : *v)
      if (m.name == name) return &m;
  return nullptr;
}

}  // namespace tern::aero
