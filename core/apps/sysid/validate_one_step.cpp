// core/apps/sysid/validate_one_step.cpp: the model's specific force and angular acceleration at
// each logged state against the measured ones: equation-error residuals (validate.hpp).
#include <cmath>
#include <limits>

#include "sysid/logged_state.hpp"
#include "sysid/validate.hpp"

namespace tern::core::sysid {

const std::array<AxisSpec, kAxes> kAxisSpecs = {{
    {"a_x", "m/s^2", "C_X", &FlightSeries::a_x},
    {"a_y", "m/s^2", "C_Y", &FlightSeries::a_y},
    {"a_z", "m/s^2", "C_Z", &FlightSeries::a_z},
    {"p_dot", "rad/s^2", "C_ell", &FlightSeries::p_dot},
    {"q_dot", "rad/s^2", "C_m", &FlightSeries::q_dot},
    {"r_dot", "rad/s^2", "C_n", &FlightSeries::r_dot},
}};

namespace {

/// Measured minus model at sample k: specific force (m/s^2) then angular acceleration (rad/s^2),
/// and the same as force and moment coefficients (validate.hpp).
struct Residual {
  std::array<double, kAxes> value, coefficient;
};

Residual residual_at(const FlightSeries& s, const Aircraft& ac, std::size_t k) {
  sim::ForcesMoments fm;
  const sim::StateVector x_dot = sim::derivative(ac, logged_state(s, k), logged_deltas(s, k), logged_wind(s, k), &fm);
  const Eigen::Vector3d a_model = fm.specific_force(ac.mass);
  const Eigen::Vector3d da(s.a_x[k] - a_model.x(), s.a_y[k] - a_model.y(), s.a_z[k] - a_model.z());
  const Eigen::Vector3d dw(s.p_dot[k] - x_dot[sim::P], s.q_dot[k] - x_dot[sim::Q], s.r_dot[k] - x_dot[sim::R]);
  Eigen::Matrix3d J;  // Beard & McLain eq. 3.10's inertia matrix
  J << ac.Jx, 0.0, -ac.Jxz, 0.0, ac.Jy, 0.0, -ac.Jxz, 0.0, ac.Jz;
  const Eigen::Vector3d dM = J * dw;  // the moment the model misses, N m
  const double qS = 0.5 * ac.rho * fm.air.Va * fm.air.Va * ac.S;
  Residual r;
  for (int i = 0; i < 3; ++i) {
    r.value[i] = da[i], r.value[3 + i] = dw[i];
    r.coefficient[i] = ac.mass * da[i] / qS;
  }
  r.coefficient[3] = dM.x() / (qS * ac.b), r.coefficient[4] = dM.y() / (qS * ac.c), r.coefficient[5] = dM.z() / (qS * ac.b);
  return r;
}

}  // namespace

std::array<AxisResidual, kAxes> one_step_residuals(const FlightSeries& s, const Aircraft& ac, const std::vector<Window>& windows) {
  std::array<double, kAxes> sum{}, sum_c{};
  std::size_t n = 0;
  for (const Window& w : windows)
    for (std::size_t k = w.begin + 1; k < w.end; ++k) {
      const Residual r = residual_at(s, ac, k);
      for (std::size_t i = 0; i < kAxes; ++i) sum[i] += r.value[i] * r.value[i], sum_c[i] += r.coefficient[i] * r.coefficient[i];
      ++n;
    }
  std::array<AxisResidual, kAxes> out{};
  for (std::size_t i = 0; i < kAxes; ++i) {
    out[i].samples = n;
    out[i].rms = n > 0 ? std::sqrt(sum[i] / static_cast<double>(n)) : std::numeric_limits<double>::quiet_NaN();
    out[i].coefficient_rms = n > 0 ? std::sqrt(sum_c[i] / static_cast<double>(n)) : std::numeric_limits<double>::quiet_NaN();
  }
  return out;
}

}  // namespace tern::core::sysid
