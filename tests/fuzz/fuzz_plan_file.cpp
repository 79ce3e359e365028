// fuzz_plan_file: libFuzzer target for QGroundControl's .plan files (core/apps/mavlink/plan_file.hpp
// parse_plan), as `tern fly --plan` reads one, then converted as an upload is (mission_items.hpp
// to_mission, fence_items.hpp to_zones and to_rally) about the plan's own home. Any bytes: a plan whose
// items convert, or PlanError / ItemError with one line that names the source; never a crash, a
// hang, another exception, a non-finite waypoint, or an error that does not name the file.
// Seeds: QGroundControl's own fixed-wing test plans and a plan with a fence, rally points, a
// DO_JUMP and a landing pattern (corpus/fuzz_plan_file).
#include <cstdint>
#include <string>

#include "fuzz_input.hpp"
#include "mavlink/fence_items.hpp"
#include "mavlink/mission_items.hpp"
#include "mavlink/plan_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tern::core::mavlink;
  const std::string source = "fuzz.plan";
  try {
    const Plan plan = parse_plan(std::string(reinterpret_cast<const char*>(data), size), source);
    if (plan.mission.size() > 65536 || plan.fence.size() > 65536 || plan.rally.size() > 65536) __builtin_trap();
    const tern::GeoOrigin home(plan.home);
    try {
      const tern::path::Mission m = to_mission(plan.mission, home);
      for (const auto& w : m.waypoints)
        if (!w.w.allFinite()) __builtin_trap();
      (void)to_zones(plan.fence, home);
      (void)to_rally(plan.rally, home);
    } catch (const ItemError& e) {
      tern::fuzz::note(e);  // what an upload refuses: its own line names the item
    }
    (void)plan_json(plan);
  } catch (const PlanError& e) {
    if (std::string(e.what()).rfind(source + ": ", 0) != 0) __builtin_trap();
    tern::fuzz::note(e);
  }
  return 0;
}
