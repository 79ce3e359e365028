// How a mission item reads in messages. See mission_item.hpp.
#include "mission_item.hpp"

#include <fmt/format.h>

namespace tern::core::ddsi {

std::string item_name(const msg::Waypoint& w) {
  switch (w.type) {
    case msg::Waypoint::loiter: return "loiter item";
    case msg::Waypoint::return_home: return "return_home item";
    case msg::Waypoint::land: return "land item";
    default: return "waypoint";
  }
}

std::string item_text(const msg::Waypoint& w) {
  const char* dir = w.loiter_direction < 0 ? "ccw" : "cw";
  switch (w.type) {
    case msg::Waypoint::loiter:
      return fmt::format(" loiter: radius {} m {}, {} turns, {} s (0: no limit){}", w.loiter_radius, dir, w.loiter_turns, w.loiter_time,
                         w.loiter_to_altitude ? ", until at its altitude" : "");
    case msg::Waypoint::return_home: return fmt::format(" return_home: radius {} m {}", w.loiter_radius, dir);
    case msg::Waypoint::land:
      return fmt::format(" land (chi_d: the runway heading): glide slope {} rad, flare {} m, decision {} m", w.land_glide_slope,
                         w.land_flare_height, w.land_decision_height);
    default: return "";
  }
}

}  // namespace tern::core::ddsi
