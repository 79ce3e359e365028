// A land item's approach, checked before the flight. See tern/path/mission_check.hpp, (a) to (d).
#include "land_check.hpp"

#include <cmath>
#include <string>

#include "entry_text.hpp"
#include "number_text.hpp"
#include "tern/math.hpp"

namespace tern::path {

namespace {

std::string m1(double v) { return number_text(v, 1); }
std::string g(double v) { return number_text(v); }
std::string deg(double rad) { return number_text(rad * kDegPerRad, 0); }

/// The straight-in approach as the path manager plans it (plugins/path landing.hpp,
/// plan_approach), on the horizontal plane; heights in m above home.
struct Final {
  Eigen::Vector2d td, entry, dir;  ///< touchdown and entry points (n, e), m; unit vector along the runway heading
  double h_td = 0.0;               ///< touchdown point above home, m
  double height = 0.0;             ///< entry point above the touchdown point, m
  double given_height = 0.0;       ///< the item before above the touchdown point, m (height unless raised)
  double length = 0.0;             ///< horizontal length of the glide path, m
  bool raised = false;             ///< given_height < kMinEntryHeights decision heights: raised to that
};

Final final_of(const MissionWaypoint& land, const Eigen::Vector3d& td, double h_before) {
  Final f;
  f.td = td.head<2>();
  f.dir = Eigen::Vector2d(std::cos(land.chi_d), std::sin(land.chi_d));
  f.h_td = -td.z();
  f.given_height = f.height = h_before - f.h_td;
  const double min_height = kMinEntryHeights * land.land.decision_height;
  if (f.height < min_height) {
    f.height = min_height;
    f.raised = true;
  }
  f.length = f.height / std::tan(land.land.glide_slope);
  f.entry = f.td - f.length * f.dir;
  return f;
}

// (a) The entry point (the touchdown point is checked as any item) and the floor, a note.
void check_final_fence(const std::string& where, const MissionWaypoint& land, const Final& f, const MissionLimits& l,
                       std::vector<MissionProblem>& out) {
  const double r = f.entry.norm();
  if (l.fence_max_distance && r > *l.fence_max_distance)
    out.push_back({false, where + "the final approach's entry point (" + m1(f.entry.x()) + ", " + m1(f.entry.y()) + ") is " + m1(r) +
                              " m from home, beyond the geofence's max_distance " + g(*l.fence_max_distance) +
                              " m: the geofence failsafe would take over on the way to it"});
  if (!l.fence_min_altitude || f.h_td >= *l.fence_min_altitude) return;
  const double floor = *l.fence_min_altitude, h_entry = f.h_td + f.height;
  if (h_entry < floor) {
    if (f.raised)  // else the item before, at the entry's altitude, draws the warning
      out.push_back({false, where + "the final approach begins " + m1(h_entry) + " m above home, below the geofence's min_altitude " +
                                g(floor) + " m: the geofence failsafe would take over on the way to its entry point"});
    return;
  }
  const double below = (floor - f.h_td) / std::tan(land.land.glide_slope);
  out.push_back({false,
                 where + "the glide path descends below the geofence's min_altitude " + g(floor) + " m in its last " + m1(below) +
                     " m: expected (the geofence floor is off from the final approach until the aircraft is above it again)",
                 true});
}

// (b) Room for the turn onto the final, from the item before (at `before`, NED m).
void check_final_turn(const std::string& where, const MissionWaypoint& land, const MissionWaypoint& prev, const Eigen::Vector2d& before,
                      const Final& f, const MissionLimits& l, std::vector<MissionProblem>& out) {
  if (!l.R_min) return;
  const double diameter = 2.0 * *l.R_min;
  const std::string turn_limit = "2 " + l.R_min_name + " = " + g(diameter) + " m";
  const Eigen::Vector2d leg = f.entry - before;
  const std::string from = prev.field.empty() ? "the item before" : prev.field;
  if (leg.norm() < diameter) {
    out.push_back({false, where + "the final approach's entry point is " + m1(leg.norm()) + " m from " + from + ", less than " +
                              turn_limit + ": no room for the turn onto the final (the path to it loops around)"});
    return;
  }
  const double turn = std::fabs(wrap_pi(land.chi_d - std::atan2(leg.y(), leg.x())));
  const Eigen::Vector2d rel = before - f.td;
  const double beside = std::fabs(f.dir.x() * rel.y() - f.dir.y() * rel.x());
  if (turn > kMaxFinalTurn && beside < diameter)
    out.push_back({false, where + "the final reverses the course from " + from + " to its entry point (a " + deg(turn) +
                              " deg turn onto heading " + g(land.chi_d) + " rad) with " + from + " " + m1(beside) +
                              " m beside the final's extended centreline, less than " + turn_limit +
                              ": the turn onto the final swings out across it (is the heading the direction of landing?)"});
}

// (c) The runway's altitude.
void check_touchdown_altitude(const std::string& where, const MissionWaypoint& land, double h_td, const MissionLimits& l,
                              std::vector<MissionProblem>& out) {
  if (std::fabs(h_td) <= kTouchdownHomeTolerance) return;
  const std::string side = h_td > 0.0 ? " above" : " below";
  const std::string what =
      land.lla ? "altitude " + g(land.w.z()) + " m MSL is " + m1(std::fabs(h_td)) + " m" + side + " home (" + g(l.origin->alt) + " m MSL)"
               : "touchdown point " + m1(std::fabs(h_td)) + " m" + side + " home (down = " + g(land.w.z()) + ")";
  out.push_back({false, where + what + ": the landing takes the runway to be there; most fields are at home's altitude"});
}

// (d) The final's length and the height it begins at.
void check_final_length(const std::string& where, const MissionWaypoint& land, const std::string& from, const Final& f,
                        std::vector<MissionProblem>& out) {
  const LandSpec& s = land.land;
  if (f.length > kMaxFinalLength)
    out.push_back({false, where + "the final approach is " + m1(f.length) + " m long (" + m1(f.height) + " m at glide_slope " +
                              g(s.glide_slope) + " rad), longer than " + g(kMaxFinalLength) +
                              " m of ground assumed flat at the runway's altitude: lower " + from + " or steepen the glide slope"});
  const double min_height = kMinApproachHeights * s.decision_height;
  if (f.given_height >= min_height) return;
  const double settle = (f.height - s.decision_height) / std::tan(s.glide_slope);
  std::string text = where + "the final approach begins at the altitude of " + from + ", " + m1(f.given_height) +
                     " m above the touchdown point, less than " + g(kMinApproachHeights) + " decision heights (" + g(min_height) + " m)";
  if (f.raised) text += ": the path manager raises it to " + m1(f.height) + " m";
  out.push_back({false, text + ": " + m1(settle) + " m of glide path above the decision height to settle after the turn onto the final"});
}

}  // namespace

void check_land(const Mission& m, const PlacedItems& pos, const MissionLimits& l, std::vector<MissionProblem>& out) {
  const auto& w = m.waypoints;
  if (w.empty() || w.back().type != ItemType::land || !pos.back()) return;
  const MissionWaypoint& land = w.back();
  const std::size_t k = w.size() - 1;
  const std::string where = entry_prefix(m, land);
  check_touchdown_altitude(where, land, -pos.back()->z(), l, out);
  if (k == 0) {
    const Final f = final_of(land, *pos.back(), -pos.back()->z());
    out.push_back({false, where + "no item before the land item: its final approach begins " + m1(f.height) +
                              " m above the touchdown point (" + g(kMinEntryHeights) +
                              " decision heights), wherever the aircraft is: put a waypoint at the approach altitude before it"});
    return;
  }
  if (!pos[k - 1]) return;
  const Final f = final_of(land, *pos.back(), -pos[k - 1]->z());
  const std::string from = w[k - 1].field.empty() ? "the item before" : w[k - 1].field;
  check_final_fence(where, land, f, l, out);
  check_final_turn(where, land, w[k - 1], pos[k - 1]->head<2>(), f, l, out);
  check_final_length(where, land, from, f, out);
}

}  // namespace tern::path
