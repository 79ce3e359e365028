// tern/geodesy.hpp: WGS-84 geodetic points and the local NED frame about a geodetic origin.
//
// Frames and units: a GeoPoint is latitude and longitude in degrees (WGS-84, north and east
// positive) and altitude in m. The local frame is NED (x north, y east, z down, m), the tangent
// plane of the WGS-84 ellipsoid at the origin. The altitude is taken as the height above the
// ellipsoid: tern's messages carry an MSL altitude and use it so for the origin and every point
// alike (the geoid's undulation over a flight's few km is what this neglects).
//
// Source: GeographicLib::LocalCartesian (Karney; exact geodetic <-> ECEF <-> local, no flat-earth
// approximation), linked into libtern_sdk.so: a plugin using GeoOrigin carries none of
// GeographicLib's code, so dlclose still unloads it.
//
// Errors: none thrown. A non-finite value, or a latitude outside [-90, 90], gives NaN
// coordinates (GeographicLib's behaviour); callers validate their inputs (tern::path::lla_to_ned
// throws MissionError for them).
#pragma once

#include <memory>

#include <Eigen/Core>

#include "tern/export.hpp"

namespace tern {

/// A geodetic position: latitude, longitude (deg, WGS-84), altitude (m).
struct GeoPoint {
  double lat = 0.0;  ///< deg, [-90, 90]
  double lon = 0.0;  ///< deg
  double alt = 0.0;  ///< m
  bool operator==(const GeoPoint& o) const { return lat == o.lat && lon == o.lon && alt == o.alt; }
  bool operator!=(const GeoPoint& o) const { return !(*this == o); }
};

/// The local NED frame about a geodetic origin: converts geodetic points to NED positions and
/// back. Copyable; each conversion is a few dozen flops (the origin's rotation is computed once).
class TERN_API GeoOrigin {
 public:
  explicit GeoOrigin(const GeoPoint& origin);
  GeoOrigin(double lat_deg, double lon_deg, double alt_m) : GeoOrigin(GeoPoint{lat_deg, lon_deg, alt_m}) {}
  ~GeoOrigin();
  GeoOrigin(const GeoOrigin& o);
  GeoOrigin& operator=(const GeoOrigin& o);
  GeoOrigin(GeoOrigin&&) noexcept;
  GeoOrigin& operator=(GeoOrigin&&) noexcept;

  /// The origin the frame was built about.
  const GeoPoint& origin() const { return origin_; }
  /// NED position (m) of a geodetic point.
  Eigen::Vector3d to_ned(const GeoPoint& p) const;
  Eigen::Vector3d to_ned(double lat_deg, double lon_deg, double alt_m) const { return to_ned(GeoPoint{lat_deg, lon_deg, alt_m}); }
  /// Geodetic point of a NED position (m).
  GeoPoint to_geodetic(const Eigen::Vector3d& ned) const;

 private:
  struct Impl;
  GeoPoint origin_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tern
