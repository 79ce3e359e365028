// The local NED frame on GeographicLib::LocalCartesian (see tern/geodesy.hpp). LocalCartesian
// works in ENU: NED is (north, east, -up).
#include "tern/geodesy.hpp"

#include <GeographicLib/LocalCartesian.hpp>

namespace tern {

struct GeoOrigin::Impl {
  GeographicLib::LocalCartesian enu;
};

GeoOrigin::GeoOrigin(const GeoPoint& origin)
    : origin_(origin), impl_(std::make_unique<Impl>(Impl{GeographicLib::LocalCartesian(origin.lat, origin.lon, origin.alt)})) {}
GeoOrigin::~GeoOrigin() = default;
GeoOrigin::GeoOrigin(const GeoOrigin& o) : origin_(o.origin_), impl_(std::make_unique<Impl>(*o.impl_)) {}
GeoOrigin& GeoOrigin::operator=(const GeoOrigin& o) {
  if (this != &o) *this = GeoOrigin(o);
  return *this;
}
GeoOrigin::GeoOrigin(GeoOrigin&&) noexcept = default;
GeoOrigin& GeoOrigin::operator=(GeoOrigin&&) noexcept = default;

Eigen::Vector3d GeoOrigin::to_ned(const GeoPoint& p) const {
  double e = 0.0, n = 0.0, u = 0.0;
  impl_->enu.Forward(p.lat, p.lon, p.alt, e, n, u);
  return {n, e, -u};
}

GeoPoint GeoOrigin::to_geodetic(const Eigen::Vector3d& ned) const {
  GeoPoint p;
  impl_->enu.Reverse(ned.y(), ned.x(), -ned.z(), p.lat, p.lon, p.alt);
  return p;
}

}  // namespace tern
