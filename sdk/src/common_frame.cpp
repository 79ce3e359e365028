#include "tern/common_frame.hpp"

#include <cmath>
#include <limits>
#include <optional>

namespace tern {

Eigen::Vector3d CommonFrame::ned(const GeoPoint& p) const { return local_.to_ned(p); }

Eigen::Vector3d CommonFrame::ned(const GeoPoint& origin, const Eigen::Vector3d& x) const {
  if (origin == reference()) return x;
  if (!about_ || about_->origin() != origin) about_.emplace(origin);
  return ned(about_->to_geodetic(x));
}

namespace {
// One frame per truth origin (a flight has one): built once, not per sample.
const CommonFrame& frame_of(const msg::State& truth) {
  thread_local std::optional<CommonFrame> frame;
  const GeoPoint o = origin_of(truth);
  if (!frame || !(frame->reference() == o)) frame.emplace(o);
  return *frame;
}
}  // namespace

Eigen::Vector3d estimate_in_truth_frame(const msg::State& estimate, const msg::State& truth) {
  if (!estimate.origin_valid || !truth.origin_valid) return position_of(estimate);
  return frame_of(truth).ned(origin_of(estimate), position_of(estimate));
}

Eigen::Vector3d fix_in_truth_frame(const msg::Gnss& fix, const msg::State& truth) {
  if (!truth.origin_valid || fix.fix_type != msg::FixType::fix_3d) {
    return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  return frame_of(truth).ned({fix.lat, fix.lon, fix.alt});
}

}  // namespace tern
