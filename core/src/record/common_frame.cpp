#include "record/common_frame.hpp"

#include <cmath>
#include <limits>
#include <optional>

#include <GeographicLib/LocalCartesian.hpp>

namespace tern::core {

struct CommonFrame::Impl {
  GeographicLib::LocalCartesian local;  // ENU about the reference
  // ENU about the last other origin asked for (an estimator keeps one origin per flight)
  std::optional<GeographicLib::LocalCartesian> about;
  GeoPoint about_origin;
};

CommonFrame::CommonFrame(const GeoPoint& reference)
    : reference_(reference),
      impl_(std::make_unique<Impl>(Impl{GeographicLib::LocalCartesian(reference.lat, reference.lon, reference.alt), {}, {}})) {}
CommonFrame::~CommonFrame() = default;
CommonFrame::CommonFrame(CommonFrame&&) noexcept = default;
CommonFrame& CommonFrame::operator=(CommonFrame&&) noexcept = default;

Eigen::Vector3d CommonFrame::ned(const GeoPoint& p) const {
  double e = 0, n = 0, u = 0;
  impl_->local.Forward(p.lat, p.lon, p.alt, e, n, u);
  return {n, e, -u};
}

Eigen::Vector3d CommonFrame::ned(const GeoPoint& origin, const Eigen::Vector3d& x) const {
  if (origin == reference_) return x;
  if (!impl_->about || !(impl_->about_origin == origin)) {
    impl_->about.emplace(origin.lat, origin.lon, origin.alt);
    impl_->about_origin = origin;
  }
  GeoPoint p;
  impl_->about->Reverse(x.y(), x.x(), -x.z(), p.lat, p.lon, p.alt);
  return ned(p);
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

}  // namespace tern::core
