// tern/msg/all.hpp: every standard message, and the list the plugin handshake fingerprints.
#pragma once

#include "tern/msg/control.hpp"
#include "tern/msg/estimator.hpp"
#include "tern/msg/mission.hpp"
#include "tern/msg/path.hpp"
#include "tern/msg/phase.hpp"
#include "tern/msg/sensors.hpp"
#include "tern/msg/state.hpp"

/// X-macro over the standard message types: X(type).
// clang-format off
#define TERN_STANDARD_MESSAGES(X)                                                       \
  X(::tern::msg::Imu) X(::tern::msg::Gnss) X(::tern::msg::Baro) X(::tern::msg::DiffPressure) \
  X(::tern::msg::Mag) X(::tern::msg::Range) X(::tern::msg::Rc) X(::tern::msg::FcuStatus) X(::tern::msg::State)     \
  X(::tern::msg::ControllerCommand) X(::tern::msg::ControllerInternals)                      \
  X(::tern::msg::Actuators) X(::tern::msg::Waypoint) X(::tern::msg::WaypointList)            \
  X(::tern::msg::CurrentPath) X(::tern::msg::FlightPhase) X(::tern::msg::MissionEdit)  \
  X(::tern::msg::Innovations) X(::tern::msg::Reference)
// clang-format on
