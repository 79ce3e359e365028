// core/host/safety/takeoff_checks.hpp: when the phase machine aborts a takeoff (phase_machine.hpp),
// as PX4's runway takeoff (RunwayTakeoff: FW_RWTO_* limits) and ArduPlane's takeoff checks
// (TKOFF_THR_MINSPD, TKOFF_GND_PITCH, the attitude limits below a safe altitude) do. Plain
// functions of the estimate; no host types.
//   the run:      the airspeed has not reached min_airspeed once the aircraft has rolled
//                 run_length m from where the takeoff began (the runway ends);
//   the attitude: |roll| above max_roll, or pitch above max_pitch or below min_pitch, while
//                 less than safe_height above where the takeoff began.
// An abort cuts the motor, levels the wings and brakes (the rollout's controller), and the flight
// ends once the aircraft has stopped (end_reason "takeoff_aborted", the criterion named).
#pragma once

#include <string>

#include "tern/msg/state.hpp"

namespace tern::core {

struct TakeoffLimits {
  double run_length = 150.0;   ///< m of runway: the Anaconda's ground roll at full throttle is ~30 m in still air
  double min_airspeed = 10.0;  ///< m/s by the end of the run (the Anaconda rotates at 12 m/s)
  /// rad (60 deg): 15 deg beyond the autopilot's own bank limit (roll_max 45 deg, which the climb's
  /// first turn uses): the controller has lost the roll
  double max_roll = 1.05;
  double max_pitch = 0.61;    ///< rad (35 deg): twice the takeoff pitch, a stall on the way
  double min_pitch = -0.35;   ///< rad (-20 deg): diving at the ground
  double safe_height = 15.0;  ///< m above the takeoff's start: above it the climb and cruise safety nets watch
};

/// Why the takeoff must be aborted ("" when it may go on): `run` m rolled or flown from the start
/// of the takeoff, `height` m above it.
std::string takeoff_abort(const msg::State& s, double run, double height, const TakeoffLimits& l);

}  // namespace tern::core
