// core/host/safety/landing_checks.hpp: the phase machine's landing decisions (phase_machine.hpp):
// is the final approach stabilised, is the aircraft on its wheels, has it stopped. Plain
// functions of the estimate, the current path (a land item's glide path, msg::CurrentPath
// `landing`) and the commanded airspeed; no host types.
//
// Stabilised approach: the criteria airline operators and the autopilots use at a decision
// height (FSF ALAR "stabilized approach": on the lateral and vertical path, speed within a
// band; ArduPlane's and PX4's landing aborts act on the same quantities). Below the land item's
// decision height and above its flare height, every one of them must hold, else a go-around:
//   cross-track     |distance from the runway's extended centre line| <= max_cross_track
//   glide path      |altitude - glide-path altitude| <= max_glide_error
//   airspeed        Va >= Va_c - max_airspeed_deficit
// On the wheels: within ground_band of the touchdown point's height with the sink stopped
// (|v_d| < settled_sink, held settled_time by the phase machine). Not the estimated height alone:
// it drifts by up to a metre over a flight (the barometer, the GNSS's vertical error; 0.7 m on
// the default mission), and a rollout begun in the air drops the aircraft with the flare cut; the
// flare law always commands a sink of at least its touchdown sink rate, so only the ground
// stops the sink.
// Stopped: ground speed below stopped_speed (held stopped_time by the phase machine).
#pragma once

#include <string>

#include "tern/msg/path.hpp"
#include "tern/msg/sensors.hpp"
#include "tern/msg/state.hpp"

namespace tern::core {

struct LandingLimits {
  double max_cross_track = 5.0;       ///< m: half a small-UAV runway's width
  double max_glide_error = 5.0;       ///< m above or below the glide path at the decision height
  double max_airspeed_deficit = 3.0;  ///< m/s below the commanded airspeed (the stall margin)
  double ground_band = 2.0;           ///< m above the runway (runway_height) within which a stopped sink is the ground
  double settled_sink = 0.15;         ///< m/s: |v_d| below this counts as a stopped sink
  double settled_time = 0.5;          ///< s
  double stopped_speed = 0.5;         ///< m/s ground speed
  double stopped_time = 1.0;          ///< s
};

/// Height of the estimate above a land path's touchdown point (r), m.
double height_above_touchdown(const msg::State& s, const msg::CurrentPath& path);

/// Distance of the estimate along the runway past the touchdown point (r), m (< 0: short of it).
double along_touchdown(const msg::State& s, const msg::CurrentPath& path);

/// The height above the runway, m: a downward range finder's (msg::Range::height) when `range`
/// holds a measurement at most Range::kFresh old at `now` (the flare and the touchdown need
/// centimetres; the altitude estimate drifts metres over a flight), else height_above_touchdown.
double runway_height(const msg::State& s, const msg::CurrentPath& path, const msg::Range* range, Nanos now);

/// Why the approach on `path` is not stabilised ("" when it is), naming the criterion and the
/// values, e.g. "cross-track 7.2 m > 5.0 m".
std::string unstabilised(const msg::State& s, const msg::CurrentPath& path, double Va_c, const LandingLimits& l);

}  // namespace tern::core
