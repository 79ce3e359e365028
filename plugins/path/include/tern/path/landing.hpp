// tern/path/landing.hpp: the geometry of a land item's straight-in approach (item.hpp LandSpec).
// Plain C++, no host types. Frames: NED, m; headings and angles in rad.
//
// The final approach is a straight glide path along the runway heading down to the touchdown
// point, as PX4's fixed-wing landing (FixedwingPositionControl, "straight landing": a glide
// slope of FW_LND_ANG to the land waypoint) and ArduPlane's AP_Landing slope landing fly it. It
// begins at the entry point, where the glide path meets the approach altitude (the altitude of
// the item flown before the land item); the path manager flies a Dubins path (book Alg. 8) to the
// entry point arriving on the runway heading, then the glide path, which the book's straight-line
// follower (eq. 10.5) tracks in three dimensions. Beyond the touchdown point the path stays at the
// runway's altitude (the follower clamps the altitude command there).
#pragma once

#include "tern/path/geometry.hpp"
#include "tern/path/item.hpp"

namespace tern::path {

struct Approach {
  Vec3 touchdown = Vec3::Zero();  ///< the aim point, NED m (its d: the runway, in the estimate's frame)
  Vec3 entry = Vec3::Zero();      ///< start of the glide path, NED m (at the approach altitude)
  Vec3 q = Vec3::UnitX();         ///< unit direction down the glide path, NED
  double heading = 0.0;           ///< runway heading, rad
  double length = 0.0;            ///< horizontal length of the glide path, m
  bool raised = false;            ///< the approach altitude was raised to the minimum (see plan_approach)
};

/// The approach to `touchdown` (NED m) on `heading` (rad) with `spec`, entered at NED down
/// `entry_d` (m). An approach altitude less than kMinEntryHeights (item.hpp) decision heights above the
/// touchdown point is raised to that (raised = true): below it there would be no stabilised
/// glide path before the decision height. Inputs must be finite (the mission reader checks).
Approach plan_approach(const Vec3& touchdown, double heading, const LandSpec& spec, double entry_d);

/// The glide path's altitude (m above the origin, -d) at the point of p's projection on it;
/// the touchdown altitude at and beyond the touchdown point, the entry altitude before the entry.
double glide_path_altitude(const Approach& a, const Vec3& p);

/// Distance of p (NED m) along the runway heading from the touchdown point, m (< 0: short of it).
double along_runway(const Approach& a, const Vec3& p);

}  // namespace tern::path
