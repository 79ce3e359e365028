// sdk/include/tern/common_frame.hpp: estimate and truth in one frame. An estimator's NED position is
// about its own origin (estimator_ekf: the first GNSS fix, itself off by the receiver's error);
// the simulator's truth is about the simulator's origin. Both State messages carry their
// origin's latitude, longitude and altitude, so every figure that compares them (flight metrics,
// `tern replay`, bench_estimation) first maps the estimate into the truth's frame, and computes
// the raw-GNSS baseline (a fix's lat/lon/alt) in that same frame. WGS-84, exact (tern::GeoOrigin of
// tern/geodesy.hpp: local tangent plane at each origin).
#pragma once

#include <optional>

#include <Eigen/Core>

#include "tern/export.hpp"
#include "tern/geodesy.hpp"
#include "tern/msg/all.hpp"

namespace tern {

/// NED (m) about a reference origin of geodetic points and of NED positions about other origins.
class TERN_API CommonFrame {
 public:
  explicit CommonFrame(const GeoPoint& reference) : local_(reference) {}
  const GeoPoint& reference() const { return local_.origin(); }

  /// A geodetic point in the reference frame, NED m.
  Eigen::Vector3d ned(const GeoPoint& p) const;
  /// A NED position about `origin` in the reference frame, NED m (the frame about `origin` is
  /// kept for the next call: not thread-safe, one CommonFrame per thread).
  Eigen::Vector3d ned(const GeoPoint& origin, const Eigen::Vector3d& ned_about_origin) const;

 private:
  GeoOrigin local_;                         // NED about the reference
  mutable std::optional<GeoOrigin> about_;  // NED about the last other origin asked for (an estimator keeps one per flight)
};

inline GeoPoint origin_of(const msg::State& s) { return {s.origin_lat, s.origin_lon, s.origin_alt}; }
inline Eigen::Vector3d position_of(const msg::State& s) { return {s.p_n, s.p_e, s.p_d}; }

/// The estimate's position in the truth's frame. When either has no origin (origin_valid false)
/// both are taken to share one frame and the estimate is returned as it is.
TERN_API Eigen::Vector3d estimate_in_truth_frame(const msg::State& estimate, const msg::State& truth);

/// A GNSS fix's position in the truth's frame (NaN when the truth has no origin or there is no fix).
TERN_API Eigen::Vector3d fix_in_truth_frame(const msg::Gnss& fix, const msg::State& truth);

}  // namespace tern
