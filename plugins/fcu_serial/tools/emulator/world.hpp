// emulator/world.hpp: the world behind an FCU program as its options set it up, shared by
// tern-fcu-emulator and tern-fcu-sil: the aircraft's start and the air, the servo throw, time
// windows of faults. Each throws std::runtime_error naming the option at fault.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "emulator.hpp"

namespace tern::fcu::emulator {

/// --wind, --turbulence and the start (--init-mode ground: settled on the gear; air: level at
/// --init-altitude and --init-airspeed), heading --init-heading.
void place_aircraft(sim::Simulator& sim, const tern::Aircraft& ac, const Options& o);

/// rad at full servo throw of aileron, elevator, rudder: --max-deflection, else the aircraft's limits.
std::array<double, 3> servo_throw(const tern::Aircraft& ac, const std::string& max_deflection);

/// A window "T0:T1" (s) as ns since power-up; empty text: none.
std::optional<std::pair<std::int64_t, std::int64_t>> time_window(const std::string& text, const std::string& option);

}  // namespace tern::fcu::emulator
