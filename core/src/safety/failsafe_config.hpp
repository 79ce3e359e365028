// core/src/safety/failsafe_config.hpp: the mission config's `failsafes:` section (failsafe.hpp says
// what each failsafe does). Every key is optional; units: s, m (altitudes above home, NED (n, e)
// polygon vertices relative to home).
//
//   failsafes:
//     gnss_loss: {enabled: true, timeout: 5, radius: 0}
//     link_loss: {enabled: true, timeout: 10, altitude: 80, radius: 0,
//                 terminate: {after: 120, action: glide}}        # action: glide | spin
//     geofence:  {max_distance: 500, min_altitude: 20, max_altitude: 150,
//                 polygon: [[600, -400], [600, 400], [-600, 400], [-600, -400]],
//                 altitude_margin: 10, radius: 0}
//
// Defaults (FailsafeConfig): gnss_loss on (5 s), link_loss on (10 s; it only acts once a ground
// station has been heard), no termination, no geofence (a `geofence:` section turns it on;
// enabled: false turns it off again). A radius of 0 leaves the orbit radius to the path manager.
#pragma once

#include <filesystem>

#include "safety/failsafe.hpp"

namespace YAML {
class Node;
}

namespace tern::core {

/// Reads `section` (null: the defaults) of config `file`. Throws ConfigError, one line naming
/// file:line:col, the field (e.g. "failsafes.geofence.max_distance") and the bad value; also for
/// a geofence that leaves home outside (a polygon around home, max_distance > 0, min < max).
FailsafeConfig parse_failsafes(const YAML::Node& section, const std::filesystem::path& file);

}  // namespace tern::core
