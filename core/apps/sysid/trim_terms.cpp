// core/apps/sysid/trim_terms.cpp: the slopes' uncertainty in the trim terms' bounds (trim_terms.hpp).
#include "sysid/trim_terms.hpp"

#include <array>
#include <cmath>
#include <numeric>
#include <string_view>
#include <vector>

namespace tern::core::sysid {

namespace {

struct Slope {
  const char* name;
  const Col* x;
};

struct TrimTerm {
  const char* name;
  std::vector<Slope> slopes;
};

double mean_over_trim(const Col& x, const Layout& L) {
  const Col m = window_means(x, L);
  return m.empty() ? 0.0 : std::accumulate(m.begin(), m.end(), 0.0) / static_cast<double>(m.size());
}

}  // namespace

void consider_slopes_in_trim_terms(Context& c, const Col& alpha, const Col& beta) {
  const AeroSamples& a = c.a;
  const std::array<TrimTerm, 4> terms = {{
      {"C_Y_0", {{"C_Y_beta", &beta}, {"C_Y_p", &a.p_hat}, {"C_Y_r", &a.r_hat}, {"C_Y_delta_a", &a.delta_a}, {"C_Y_delta_r", &a.delta_r}}},
      {"C_ell_0",
       {{"C_ell_beta", &beta}, {"C_ell_p", &a.p_hat}, {"C_ell_r", &a.r_hat}, {"C_ell_delta_a", &a.delta_a}, {"C_ell_delta_r", &a.delta_r}}},
      {"C_m_0", {{"C_m_alpha", &alpha}, {"C_m_q", &a.q_hat}, {"C_m_delta_e", &a.delta_e}}},
      {"C_n_0", {{"C_n_beta", &beta}, {"C_n_p", &a.p_hat}, {"C_n_r", &a.r_hat}, {"C_n_delta_a", &a.delta_a}, {"C_n_delta_r", &a.delta_r}}},
  }};
  for (const TrimTerm& t : terms) {
    CoefficientEstimate* e = find_estimate(c.result, t.name);
    if (e == nullptr || !e->identified) continue;
    double variance = e->std_error * e->std_error;
    for (const Slope& s : t.slopes) {
      const CoefficientEstimate* slope = find_estimate(c.result, s.name);
      if (slope == nullptr) continue;
      const double sigma = slope->identified ? slope->std_error : kPriorUncertainty * std::abs(slope->prior);
      const double m = mean_over_trim(*s.x, c.L);
      variance += sigma * sigma * m * m;
    }
    if (t.name == std::string_view("C_ell_0")) {
      // the propeller's torque, added back from the prior's propeller (aero_samples.hpp), is a kept prior too
      const double m = mean_over_trim(a.C_ell_prop, c.L);
      variance += kPriorUncertainty * kPriorUncertainty * m * m;
    }
    e->std_error = std::sqrt(variance);
  }
}

}  // namespace tern::core::sysid
