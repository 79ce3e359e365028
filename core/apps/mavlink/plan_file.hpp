// core/apps/mavlink/plan_file.hpp: QGroundControl's plan files (.plan, JSON) <-> MAVLink items, so
// that a plan made in QGroundControl flies in tern unchanged (`tern fly CONFIG --plan FILE.plan`)
// and a tern mission opens in QGroundControl (`tern export plan`). docs/ground-station.md, "Plan files".
//
// The format (QGroundControl's PlanMasterController, fileType "Plan", version 1; what its own
// test/plans/*.plan hold):
//   mission.plannedHomePosition   [lat deg, lon deg, alt m MSL]: home, where the items are placed about
//   mission.items[]               "type": "SimpleItem": command, frame, params[7] (lat, lon and alt in
//                                 params 5-7, degrees; null: NaN), autoContinue;
//                                 "type": "ComplexItem": a survey or corridor scan
//                                 (TransectStyleComplexItem.Items: the SimpleItems QGroundControl
//                                 generated), or "complexItemType": "fwLandingPattern" (landCoordinate,
//                                 landingApproachCoordinate or loiterCoordinate, loiterRadius,
//                                 loiterClockwise, useLoiterToAlt, altitudesAreRelative): DO_LAND_START,
//                                 NAV_LOITER_TO_ALT (or NAV_WAYPOINT) at the approach point, NAV_LAND,
//                                 as QGroundControl uploads it
//   geoFence.polygons[]           {inclusion: bool, polygon: [[lat, lon], ...]}
//   geoFence.circles[]            {inclusion: bool, circle: {center: [lat, lon], radius: m}}
//   rallyPoints.points[]          [lat, lon, alt]  (alt m above home, GLOBAL_RELATIVE_ALT as QGroundControl sends it)
// The items become MISSION_ITEM_INTs (degE7), to be checked and converted by mission_items.hpp and
// fence_items.hpp as an upload is: what an upload refuses, a plan refuses, naming the same item.
// Errors: PlanError (a std::runtime_error), one line naming the file and the JSON field
// ("plan.plan: mission.items[3].params[4]: expected a number or null, got \"x\"").
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "mavlink/mission_messages.hpp"
#include "tern/geodesy.hpp"

namespace tern::core::mavlink {

class PlanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A plan's three lists, as a ground station uploads them (seq from 0, mission_type set).
struct Plan {
  GeoPoint home;                        ///< plannedHomePosition (lat deg, lon deg, alt m MSL)
  double cruise_speed = 0.0;            ///< mission.cruiseSpeed, m/s: the planner's speed for its time estimates
  std::vector<MissionItemInt> mission;  ///< MISSION items
  std::vector<MissionItemInt> fence;    ///< FENCE items (polygon vertices, circles)
  std::vector<MissionItemInt> rally;    ///< RALLY items
};

/// The largest plan file read, bytes (QGroundControl's 1000-item plans are ~500 KB).
inline constexpr std::uintmax_t kMaxPlanBytes = 16u << 20;

/// Reads a .plan file. Throws PlanError (unreadable, not JSON, not a plan, a field of the wrong type).
Plan read_plan(const std::filesystem::path& file);

/// Parses a plan's text; `source` names it in errors. Throws PlanError.
Plan parse_plan(const std::string& text, const std::string& source);

/// The plan as QGroundControl writes it (SimpleItems, geoFence, rallyPoints), JSON text.
std::string plan_json(const Plan& plan);

}  // namespace tern::core::mavlink
