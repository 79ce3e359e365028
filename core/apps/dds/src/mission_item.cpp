// A mission item on tern's wire. See mission_item.hpp.
#include "mission_item.hpp"

#include <fmt/format.h>

namespace tern::core::ddsi {

void to_mission_item(const msg::Waypoint& w, tern_msgs::msg::MissionItem& out) {
  for (int i = 0; i < 3; ++i) out.w()[static_cast<std::size_t>(i)] = w.w[i];
  out.lla(w.lla);
  out.chi_d(w.chi_d);
  out.use_chi(w.use_chi);
  out.Va_d(w.Va_d);
  out.type(w.type);
  out.loiter_radius(w.loiter_radius);
  out.loiter_direction(w.loiter_direction);
  out.loiter_time(w.loiter_time);
  out.loiter_turns(w.loiter_turns);
  out.land_glide_slope(w.land_glide_slope);
  out.land_flare_height(w.land_flare_height);
  out.land_decision_height(w.land_decision_height);
}

msg::Waypoint from_mission_item(const tern_msgs::msg::MissionItem& in) {
  msg::Waypoint w;
  for (int i = 0; i < 3; ++i) w.w[i] = in.w()[static_cast<std::size_t>(i)];
  w.lla = in.lla();
  w.chi_d = in.chi_d();
  w.use_chi = in.use_chi();
  w.Va_d = in.Va_d();
  w.type = in.type();
  w.loiter_radius = in.loiter_radius();
  w.loiter_direction = in.loiter_direction();
  w.loiter_time = in.loiter_time();
  w.loiter_turns = in.loiter_turns();
  w.land_glide_slope = in.land_glide_slope();
  w.land_flare_height = in.land_flare_height();
  w.land_decision_height = in.land_decision_height();
  return w;
}

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
      return fmt::format(" loiter: radius {} m {}, {} turns, {} s (0: no limit)", w.loiter_radius, dir, w.loiter_turns, w.loiter_time);
    case msg::Waypoint::return_home: return fmt::format(" return_home: radius {} m {}", w.loiter_radius, dir);
    case msg::Waypoint::land:
      return fmt::format(" land (chi_d: the runway heading): glide slope {} rad, flare {} m, decision {} m", w.land_glide_slope,
                         w.land_flare_height, w.land_decision_height);
    default: return "";
  }
}

}  // namespace tern::core::ddsi
