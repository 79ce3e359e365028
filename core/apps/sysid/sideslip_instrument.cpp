// core/apps/sysid/sideslip_instrument.cpp: the lateral model's sideslip (sideslip_instrument.hpp).
#include "sysid/sideslip_instrument.hpp"

#include <complex>
#include <stdexcept>

#include <Eigen/LU>

#include "tern/math.hpp"

namespace tern::core::sysid {

Eigen::VectorXcd modelled_sideslip(const tern::aero::LinearModel& m, const std::vector<double>& f_hz, const Eigen::VectorXcd& delta_a,
                                   const Eigen::VectorXcd& delta_r) {
  const auto n = static_cast<Eigen::Index>(f_hz.size());
  if (delta_a.size() != n || delta_r.size() != n)
    throw std::invalid_argument("modelled_sideslip: spectra and frequencies differ in length");
  using Mat = Eigen::Matrix<std::complex<double>, 5, 5>;
  const Mat A = m.A_lat.cast<std::complex<double>>();
  const Eigen::Matrix<std::complex<double>, 5, 2> B = m.B_lat.cast<std::complex<double>>();
  Eigen::VectorXcd beta(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::complex<double> s(0.0, 2.0 * kPi * f_hz[static_cast<std::size_t>(i)]);
    const Eigen::Matrix<std::complex<double>, 5, 1> x =
        (s * Mat::Identity() - A).partialPivLu().solve(B * Eigen::Vector2cd(delta_a[i], delta_r[i]));
    beta[i] = x[0] / m.Va;
  }
  return beta;
}

}  // namespace tern::core::sysid
