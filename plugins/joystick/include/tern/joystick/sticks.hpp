// tern/joystick/sticks.hpp: from a game controller's raw axes to a pilot's sticks, as an RC
// transmitter's channel settings do it: channel mapping, reversal, deadband and expo. Plain C++,
// no SDL, no host types.
//
// A raw axis is -1..1 (SDL's -32768..32767 divided by 32767, clamped). For each stick:
//   x = raw axis `axis` of the controller, negated when reversed
//   deadband d (0..0.5): |x| <= d gives 0; beyond, the rest is stretched back to 0..1:
//       x' = sign(x) (|x| - d) / (1 - d)
//   expo e (0..1), on roll, pitch and yaw only (the usual transmitter curve, softer near centre):
//       y = (1 - e) x' + e x'^3
// Roll, pitch and yaw are -1..1 (right, nose up, nose right positive: msg::Rc). The throttle is
// 0..1, y mapped by (y + 1) / 2: a spring-centred stick gives half throttle at centre; with a
// controller's left stick (up is negative in SDL) reverse it.
#pragma once

#include <array>

namespace tern::joystick {

struct StickMap {
  int axis = 0;          ///< controller axis index (SDL_GameControllerAxis: 0 left x ... 5 right trigger)
  bool reverse = false;  ///< negate the axis
};

struct StickShaping {
  std::array<StickMap, 4> map{};  ///< roll, pitch, yaw, throttle
  double deadband = 0.05;         ///< 0..0.5, of full deflection
  double expo = 0.3;              ///< 0..1
};

struct Sticks {
  double roll = 0.0, pitch = 0.0, yaw = 0.0;  ///< -1..1
  double throttle = 0.0;                      ///< 0..1
};

/// Deadband then expo on one signed axis value (-1..1, clamped first).
double shape(double x, double deadband, double expo);

/// The four sticks from the controller's raw axes (-1..1, indexed by StickMap::axis; an index
/// outside `axes` reads 0).
Sticks sticks_from_axes(const std::array<double, 6>& axes, const StickShaping& s);

}  // namespace tern::joystick
