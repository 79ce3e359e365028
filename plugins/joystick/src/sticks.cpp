#include "tern/joystick/sticks.hpp"

#include <algorithm>
#include <cmath>

namespace tern::joystick {

double shape(double x, double deadband, double expo) {
  x = std::clamp(x, -1.0, 1.0);
  const double a = std::abs(x);
  if (a <= deadband) return 0.0;
  const double v = std::copysign((a - deadband) / (1.0 - deadband), x);
  return (1.0 - expo) * v + expo * v * v * v;
}

Sticks sticks_from_axes(const std::array<double, 6>& axes, const StickShaping& s) {
  const auto axis = [&](const StickMap& m) {
    const double raw = m.axis >= 0 && m.axis < static_cast<int>(axes.size()) ? axes[static_cast<std::size_t>(m.axis)] : 0.0;
    return m.reverse ? -raw : raw;
  };
  Sticks out;
  out.roll = shape(axis(s.map[0]), s.deadband, s.expo);
  out.pitch = shape(axis(s.map[1]), s.deadband, s.expo);
  out.yaw = shape(axis(s.map[2]), s.deadband, s.expo);
  out.throttle = (shape(axis(s.map[3]), s.deadband, 0.0) + 1.0) / 2.0;
  return out;
}

}  // namespace tern::joystick
