// tern/path/landing.hpp: the geometry of a land item's straight-in approach (item.hpp LandSpec).
// Plain C++, no host types. Frames: NED, m; headings and angles in rad.
//
// The final approach is a straight glide path along the runway heading down to the touchdown
// point, as PX4's fixed-wing landing (FixedwingPositionControl, "straight landing": a glide
// slope of FW_LND_ANG to the land waypoint) and ArduPlane's AP_Landing slope landing fly it. It
// begins at the entry point, where the glide path meets the approach altitude (the altitude of
// the item flown before the land item); the path manager flies a Dubins path (book Alg. 8) to the
// entry point arriving on the runway heading, then the glide path, which the book's straight-line
// follower (eq. 10.5) tracks in three dimensions. Beyond the aim point the path stays at the
// runway's altitude (the follower clamps the altitude command there).
//
// The aim point moved for the wind (ArduPlane's AP_Landing_Slope.cpp, setup_landing_glide_slope:
// "distance to flare is based on ground speed ... This takes into account the wind"): the flare
// floats the aircraft beyond the point where the glide path meets the runway, by about the ground
// speed times the flare's duration. The glide path is therefore aimed at a point before the
// touchdown point: the flare then begins Vg * flare_time before the touchdown point, at the flare
// height, which the glide path reaches flare_height / tan(glide_slope) before its aim point. Into
// a headwind the float is shorter and the aim point moves towards (or beyond) the touchdown point.
#pragma once

#include "tern/path/geometry.hpp"
#include "tern/path/item.hpp"

namespace tern::path {

struct Approach {
  Vec3 touchdown = Vec3::Zero();  ///< the land item's touchdown point, NED m (its d: the runway, in the estimate's frame)
  Vec3 aim = Vec3::Zero();        ///< where the glide path meets the runway, NED m: aim_offset before the touchdown point
  double aim_offset = 0.0;        ///< m along the runway heading from the aim point to the touchdown point (< 0: aim beyond it)
  Vec3 entry = Vec3::Zero();      ///< start of the glide path, NED m (at the approach altitude)
  Vec3 q = Vec3::UnitX();         ///< unit direction down the glide path, NED
  double heading = 0.0;           ///< runway heading, rad
  double length = 0.0;            ///< horizontal length of the glide path (entry to aim point), m
  bool raised = false;            ///< the approach altitude was raised to the minimum (see plan_approach)
};

/// The approach to `touchdown` (NED m) on `heading` (rad) with `spec`, entered at NED down
/// `entry_d` (m), its glide path aimed `aim_offset` m before the touchdown point (aim_offset(),
/// limited to half the glide path's length either way, as ArduPlane limits its flare distance).
/// An approach altitude less than kMinEntryHeights (item.hpp) decision heights above the
/// touchdown point is raised to that (raised = true): below it there would be no stabilised
/// glide path before the decision height. Inputs must be finite (the mission reader checks).
Approach plan_approach(const Vec3& touchdown, double heading, const LandSpec& spec, double entry_d, double aim_offset = 0.0);

/// Ground speed along the runway heading `heading` (rad) flying at airspeed Va (m/s) in the
/// horizontal wind `wind` (NED m/s, the direction it blows to), crabbed onto the runway's line:
/// sqrt(Va^2 - w_cross^2) + w_along, m/s, >= 0 (0 when the crosswind exceeds Va).
double runway_ground_speed(double Va, const Vec3& wind, double heading);

/// How far before the touchdown point the glide path should meet the runway, m (see the file
/// comment): Vg * flare_time - flare_height / tan(glide_slope), with Vg the ground speed along the
/// runway (m/s, >= 0) and flare_time the flare's expected duration (s, >= 0); 0 when flare_time
/// is 0 (the glide path aimed at the touchdown point).
double aim_offset(double Vg, double flare_time, const LandSpec& spec);

/// The glide path's altitude (m above the origin, -d) at the point of p's projection on it;
/// the touchdown altitude at and beyond the aim point, the entry altitude before the entry.
double glide_path_altitude(const Approach& a, const Vec3& p);

/// Distance of p (NED m) along the runway heading from the touchdown point, m (< 0: short of it).
double along_runway(const Approach& a, const Vec3& p);

}  // namespace tern::path
