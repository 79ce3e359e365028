// core/apps/sysid/sideslip_instrument.cpp: the lateral model's sideslip (sideslip_instrument.hpp).
#include "sysid/sideslip_instrument.hpp"

#include <complex>
#include <stdexcept>

#include <Eigen/LU>

#include "tern/math.hpp"

namespace tern::core::sysid {

namespace {

/// Row `out` of x(f) = (j 2 pi f I - A)^-1 B u(f), over Va, at every frequency.
Eigen::VectorXcd response(const Eigen::Matrix<double, 5, 5>& A, const Eigen::Matrix<double, 5, 2>& B, int out, double Va,
                          const std::vector<double>& f_hz, const Eigen::VectorXcd& u1, const Eigen::VectorXcd& u2) {
  const auto n = static_cast<Eigen::Index>(f_hz.size());
  if (u1.size() != n || u2.size() != n) throw std::invalid_argument("modelled flow angle: spectra and frequencies differ in length");
  using Mat = Eigen::Matrix<std::complex<double>, 5, 5>;
  const Mat Ac = A.cast<std::complex<double>>();
  const Eigen::Matrix<std::complex<double>, 5, 2> Bc = B.cast<std::complex<double>>();
  Eigen::VectorXcd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::complex<double> s(0.0, 2.0 * kPi * f_hz[static_cast<std::size_t>(i)]);
    const Eigen::Matrix<std::complex<double>, 5, 1> x =
        (s * Mat::Identity() - Ac).partialPivLu().solve(Bc * Eigen::Vector2cd(u1[i], u2[i]));
    y[i] = x[out] / Va;
  }
  return y;
}

}  // namespace

Eigen::VectorXcd modelled_sideslip(const tern::aero::LinearModel& m, const std::vector<double>& f_hz, const Eigen::VectorXcd& delta_a,
                                   const Eigen::VectorXcd& delta_r) {
  return response(m.A_lat, m.B_lat, 0, m.Va, f_hz, delta_a, delta_r);  // x_lat[0] = v
}

Eigen::VectorXcd modelled_roll_rate(const tern::aero::LinearModel& m, const std::vector<double>& f_hz, const Eigen::VectorXcd& delta_a,
                                    const Eigen::VectorXcd& delta_r) {
  return response(m.A_lat, m.B_lat, 1, m.Va, f_hz, delta_a, delta_r);  // x_lat[1] = p
}

Eigen::VectorXcd modelled_yaw_rate(const tern::aero::LinearModel& m, const std::vector<double>& f_hz, const Eigen::VectorXcd& delta_a,
                                   const Eigen::VectorXcd& delta_r) {
  return response(m.A_lat, m.B_lat, 2, m.Va, f_hz, delta_a, delta_r);  // x_lat[2] = r
}

Eigen::VectorXcd modelled_alpha(const tern::aero::LinearModel& m, const std::vector<double>& f_hz, const Eigen::VectorXcd& delta_e,
                                const Eigen::VectorXcd& delta_t) {
  return response(m.A_lon, m.B_lon, 1, m.Va, f_hz, delta_e, delta_t);  // x_lon[1] = w
}

}  // namespace tern::core::sysid
