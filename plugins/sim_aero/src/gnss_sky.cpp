// The GNSS antenna's sky view and the receiver's solution (see gnss_sky.hpp).
#include "tern_sim_aero/gnss_sky.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <boost/random/normal_distribution.hpp>

#include "tern/math.hpp"

namespace tern::sim {

namespace {
constexpr std::uint64_t kSkyStream = 0x5a7e111e5ull;  // the sky's own stream of the seed

using Geometry = Eigen::Matrix<double, Eigen::Dynamic, 4>;

// Rows [-los^T, 1]: a range's sensitivity to the receiver's position (NED) and clock.
Geometry geometry(const std::vector<Eigen::Vector3d>& los) {
  Geometry H(static_cast<Eigen::Index>(los.size()), 4);
  for (std::size_t i = 0; i < los.size(); ++i) H.row(static_cast<Eigen::Index>(i)) << -los[i].transpose(), 1.0;
  return H;
}

// The least-squares solution's error (position or velocity, NED) from the ranges' errors e.
Eigen::Vector3d solution_error(const Geometry& H, const Eigen::VectorXd& e) {
  const Eigen::Matrix4d M = H.transpose() * H;
  return M.ldlt().solve(H.transpose() * e).head<3>();
}

void check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("gnss sky: " + what);
}
}  // namespace

Dops dilutions_of_precision(const std::vector<Eigen::Vector3d>& los) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (los.size() < 4) return {kInf, kInf, kInf};
  const Geometry H = geometry(los);
  const Eigen::Matrix4d M = H.transpose() * H;
  const Eigen::LDLT<Eigen::Matrix4d> ldlt(M);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-9)) return {kInf, kInf, kInf};
  const Eigen::Matrix4d G = ldlt.solve(Eigen::Matrix4d::Identity());
  return {std::sqrt(G(0, 0) + G(1, 1)), std::sqrt(G(2, 2)), std::sqrt(G(0, 0) + G(1, 1) + G(2, 2))};
}

GnssSky::GnssSky(const GnssSkyParams& p, std::uint64_t seed) : p_(p), seed_(seed) {
  check(p.satellites >= 0 && p.satellites <= 64, "satellites " + std::to_string(p.satellites) + " outside 0..64");
  check(p.elevation_mask >= 0.0 && p.elevation_mask < 0.5 * tern::kPi, "elevation_mask outside [0, 90) deg");
  check(std::fabs(p.antenna_cutoff) < 0.5 * tern::kPi, "antenna_cutoff outside (-90, 90) deg");
  check(p.max_acceleration <= 0.0 || p.lag_tau > 0.0, "a platform bound needs lag_tau > 0");
  check(p.reacquisition >= 0.0 && p.horizontal_sigma >= 0.0 && p.velocity_sigma >= 0.0 && p.range_tau >= 0.0 && p.pdop_mask >= 0.0 &&
            p.max_acceleration >= 0.0,
        "a negative time, sigma or acceleration");
  reset();
}

// The constellation: azimuth i of n in its own 360/n-degree sector, sin(elevation) uniform above
// the mask; then the range errors from their steady state, sized by the whole sky's DOPs.
void GnssSky::reset() {
  rng_.seed(seed_ ^ kSkyStream);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  boost::random::normal_distribution<double> n(0.0, 1.0);
  const int count = p_.satellites;
  los_.clear();
  range_error_.clear();
  for (int i = 0; i < count; ++i) {
    const double az = 2.0 * tern::kPi * (i + u(rng_)) / count;
    const double s_mask = std::sin(p_.elevation_mask);
    const double el = std::asin(s_mask + (1.0 - s_mask) * u(rng_));
    los_.emplace_back(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), -std::sin(el));
  }
  whole_ = dilutions_of_precision(los_);
  range_sigma_ = std::isfinite(whole_.h) ? p_.horizontal_sigma * std::sqrt(2.0) / whole_.h : 0.0;
  range_rate_sigma_ = std::isfinite(whole_.p) ? p_.velocity_sigma * std::sqrt(3.0) / whole_.p : 0.0;
  for (int i = 0; i < count; ++i) range_error_.push_back(range_sigma_ * n(rng_));
  in_view_since_.assign(static_cast<std::size_t>(count), -std::numeric_limits<double>::infinity());
  tracked_.assign(static_cast<std::size_t>(count), true);
  velocity_prev_.setZero();
  lag_.setZero();
  velocity_started_ = false;
}

// A satellite is in view while its elevation above the antenna's plane is at least the cutoff;
// tracked once it has been in view for the reacquisition time.
void GnssSky::update_tracking(double t, const Eigen::Vector3d& boresight_ned) {
  const double s_cut = std::sin(p_.antenna_cutoff);
  for (std::size_t i = 0; i < los_.size(); ++i) {
    if (los_[i].dot(boresight_ned) < s_cut) {
      in_view_since_[i] = std::numeric_limits<double>::quiet_NaN();
      tracked_[i] = false;
      continue;
    }
    if (std::isnan(in_view_since_[i])) in_view_since_[i] = t;
    if (t - in_view_since_[i] >= p_.reacquisition - 1e-9) tracked_[i] = true;  // to the nanosecond: t sums the fixes' dt
  }
}

// Of the truth's velocity change since the last fix, what exceeds max_acceleration dt enters the
// lag (the output does not follow it), which decays with lag_tau.
Eigen::Vector3d GnssSky::platform_lag(double dt, const Eigen::Vector3d& velocity_ned) {
  if (p_.max_acceleration <= 0.0 || !velocity_started_) {
    velocity_prev_ = velocity_ned;
    velocity_started_ = true;
    return Eigen::Vector3d::Zero();
  }
  const Eigen::Vector3d change = velocity_ned - velocity_prev_;
  velocity_prev_ = velocity_ned;
  const double bound = p_.max_acceleration * std::max(dt, 0.0);
  const Eigen::Vector3d beyond = change.norm() > bound ? Eigen::Vector3d(change * (1.0 - bound / change.norm())) : Eigen::Vector3d::Zero();
  lag_ = std::exp(-std::max(dt, 0.0) / p_.lag_tau) * lag_ - beyond;
  return lag_;
}

// Every satellite's errors advance, tracked or not (a fixed sequence of draws): the range errors'
// Gauss-Markov step; the range-rate errors, white, returned.
Eigen::VectorXd GnssSky::advance_errors(double dt) {
  boost::random::normal_distribution<double> n(0.0, 1.0);
  const double phi = p_.range_tau > 0.0 ? std::exp(-std::max(dt, 0.0) / p_.range_tau) : 0.0;
  Eigen::VectorXd rate_error(static_cast<Eigen::Index>(los_.size()));
  for (std::size_t i = 0; i < los_.size(); ++i) {
    range_error_[i] = phi * range_error_[i] + range_sigma_ * std::sqrt(1.0 - phi * phi) * n(rng_);
    rate_error(static_cast<Eigen::Index>(i)) = range_rate_sigma_ * n(rng_);
  }
  return rate_error;
}

// The tracked set's solution less the whole sky's, for the range errors and the range-rate errors.
void GnssSky::solution_errors(const Eigen::VectorXd& rate_error, GnssSkyFix& f) const {
  std::vector<Eigen::Vector3d> seen;
  Eigen::VectorXd range_seen(f.tracked), rate_seen(f.tracked);
  for (std::size_t i = 0; i < los_.size(); ++i) {
    if (!tracked_[i]) continue;
    const auto k = static_cast<Eigen::Index>(seen.size());
    range_seen(k) = range_error_[i];
    rate_seen(k) = rate_error(static_cast<Eigen::Index>(i));
    seen.push_back(los_[i]);
  }
  const Eigen::Map<const Eigen::VectorXd> range(range_error_.data(), static_cast<Eigen::Index>(range_error_.size()));
  const Geometry H_all = geometry(los_), H_seen = geometry(seen);
  f.position_error = solution_error(H_seen, range_seen) - solution_error(H_all, range);
  f.velocity_error += solution_error(H_seen, rate_seen) - solution_error(H_all, rate_error);
}

GnssSkyFix GnssSky::step(double t, double dt, const Eigen::Vector3d& boresight_ned, const Eigen::Vector3d& velocity_ned) {
  GnssSkyFix f;
  f.velocity_error = platform_lag(dt, velocity_ned);
  f.velocity_lag = f.velocity_error.norm();
  if (!modelled()) return f;
  const Eigen::VectorXd rate_error = advance_errors(dt);
  update_tracking(t, boresight_ned);
  std::vector<Eigen::Vector3d> seen;
  for (std::size_t i = 0; i < los_.size(); ++i)
    if (tracked_[i]) seen.push_back(los_[i]);
  f.tracked = static_cast<int>(seen.size());
  const Dops now = dilutions_of_precision(seen);
  f.fix = std::isfinite(now.p) && (p_.pdop_mask <= 0.0 || now.p <= p_.pdop_mask);
  if (!f.fix) return f;
  f.hdop = now.h;
  f.vdop = now.v;
  f.pdop = now.p;
  f.hdop_ratio = now.h / whole_.h;
  f.vdop_ratio = now.v / whole_.v;
  f.pdop_ratio = now.p / whole_.p;
  if (f.tracked < static_cast<int>(los_.size())) solution_errors(rate_error, f);
  return f;
}

}  // namespace tern::sim
