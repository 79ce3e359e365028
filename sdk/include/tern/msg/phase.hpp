// tern/msg/phase.hpp: the flight phase, topic `flight_phase` (published by the host's phase
// machine; the phase router runs the controller the mission config names for it).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

#include "tern/time.hpp"

namespace tern::msg {

/// preflight: on the ground, motor off, no controller running, until the arming checks pass
/// (estimator aligned, GNSS good, aircraft at rest); then takeoff.
/// A land item (tern/path/item.hpp) is flown approach (its final glide path) -> flare (below the
/// flare height) -> rollout (on the wheels: motor off, steering, brakes) -> stopped (at rest:
/// the flight ends, end_reason "landed"); a go-around returns to climb. `landing` and `loiter`
/// are kept for configs that name them (flown as cruise).
enum class Phase : std::uint8_t {
  takeoff = 0,
  climb = 1,
  cruise = 2,
  landing = 3,
  loiter = 4,
  preflight = 5,
  approach = 6,
  flare = 7,
  rollout = 8,
  stopped = 9
};

inline constexpr std::string_view phase_name(Phase p) {
  switch (p) {
    case Phase::takeoff: return "takeoff";
    case Phase::climb: return "climb";
    case Phase::cruise: return "cruise";
    case Phase::landing: return "landing";
    case Phase::loiter: return "loiter";
    case Phase::preflight: return "preflight";
    case Phase::approach: return "approach";
    case Phase::flare: return "flare";
    case Phase::rollout: return "rollout";
    case Phase::stopped: return "stopped";
  }
  return "unknown";
}

/// Every phase, in code order.
inline constexpr std::array<Phase, 10> kAllPhases = {Phase::takeoff,   Phase::climb,    Phase::cruise, Phase::landing, Phase::loiter,
                                                     Phase::preflight, Phase::approach, Phase::flare,  Phase::rollout, Phase::stopped};

inline constexpr std::optional<Phase> phase_from_name(std::string_view s) {
  for (auto p : kAllPhases)
    if (phase_name(p) == s) return p;
  return std::nullopt;
}

/// The phases a `phases:` table may give a controller (preflight and stopped run none).
inline constexpr std::array<Phase, 8> kControllerPhases = {Phase::takeoff, Phase::climb,    Phase::cruise, Phase::landing,
                                                           Phase::loiter,  Phase::approach, Phase::flare,  Phase::rollout};

/// In the air: after the takeoff's climb-out and before the rollout (the failsafes' airborne).
inline constexpr bool airborne(Phase p) {
  return p == Phase::climb || p == Phase::cruise || p == Phase::loiter || p == Phase::landing || p == Phase::approach || p == Phase::flare;
}

/// On the glide path or in the flare: the phases a go-around leaves (and where the floors of the
/// geofence and the safety monitor are disarmed).
inline constexpr bool on_final(Phase p) { return p == Phase::approach || p == Phase::flare; }

/// A land item's phases, from the final approach to stopped on the runway.
inline constexpr bool landing_phase(Phase p) { return on_final(p) || p == Phase::rollout || p == Phase::stopped; }

struct FlightPhase {
  static constexpr std::string_view type_name = "tern/FlightPhase";
  Nanos stamp = 0;
  Phase phase = Phase::takeoff;
  Phase previous = Phase::takeoff;
  Nanos since = 0;  ///< flight time at which the current phase began, ns
  template <class V>
  static constexpr void describe(V& v) {
    v(&FlightPhase::stamp, "stamp", "ns");
    v(&FlightPhase::phase, "phase", "enum");
    v(&FlightPhase::previous, "previous", "enum");
    v(&FlightPhase::since, "since", "ns");
  }
};

}  // namespace tern::msg
