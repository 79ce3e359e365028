// mapping.cpp: see tern_fcu_serial/mapping.hpp.
#include "tern_fcu_serial/mapping.hpp"

#include <algorithm>
#include <cmath>

namespace tern::fcu {

namespace {
const char* kSurface[] = {"aileron", "elevator", "rudder", "throttle"};
double finite_or_zero(double v) { return std::isfinite(v) ? v : 0.0; }
}  // namespace

int channel_index(const std::string& name) {
  for (std::size_t i = 0; i < kChannelNames.size(); ++i)
    if (name == kChannelNames[i]) return static_cast<int>(i);
  throw std::invalid_argument("'" + name + "' is not one of the firmware's channels Fx Fy Fz Qx Qy Qz");
}

void ActuatorMap::validate() const {
  for (int i = 0; i < 4; ++i) {
    if (channel[i] < 0 || channel[i] > 5)
      throw std::invalid_argument(std::string(kSurface[i]) + " channel " + std::to_string(channel[i]) + " is outside 0..5 (Fx..Qz)");
    for (int j = 0; j < i; ++j)
      if (channel[i] == channel[j])
        throw std::invalid_argument(std::string(kSurface[i]) + " and " + kSurface[j] + " share channel " + kChannelNames[channel[i]]);
    if (sign[i] != 1.0 && sign[i] != -1.0)
      throw std::invalid_argument(std::string(kSurface[i]) + " sign must be +1 or -1, got " + std::to_string(sign[i]));
  }
  for (int i = 0; i < 3; ++i)
    if (!(max_deflection[i] > 0.0) || !std::isfinite(max_deflection[i]))
      throw std::invalid_argument(std::string(kSurface[i]) + " maximum deflection must be > 0 rad, got " +
                                  std::to_string(max_deflection[i]));
}

mavlink::OffboardControl to_offboard(const Surfaces& s, const ActuatorMap& map) {
  mavlink::OffboardControl c;
  c.mode = kModePassThrough;
  const double d[3] = {s.delta_a, s.delta_e, s.delta_r};
  for (int i = 0; i < 3; ++i)
    c.u[map.channel[i]] = static_cast<float>(std::clamp(finite_or_zero(d[i]) / map.max_deflection[i], -1.0, 1.0) * map.sign[i]);
  const double t = std::clamp(finite_or_zero(s.delta_t), 0.0, 1.0);
  c.u[map.channel[3]] = static_cast<float>(map.sign[3] > 0 ? t : -t);
  c.ignore = 0x3C0;  // u[6..9] (rosflight.xml IGNORE_VALUE6..9); u[0..5] all active
  return c;
}

void RcMap::validate() const {
  std::array<int, 8> all{};
  for (int i = 0; i < 4; ++i) {
    all[i] = stick_channel[i];
    all[4 + i] = aux_channel[i];
  }
  for (int i = 0; i < 8; ++i) {
    if (all[i] < 0 || all[i] > 17) throw std::invalid_argument("RC channel " + std::to_string(all[i]) + " is outside 0..17");
    for (int j = 0; j < i; ++j)
      if (all[i] == all[j]) throw std::invalid_argument("RC channel " + std::to_string(all[i]) + " is mapped twice");
  }
  for (double s : sign)
    if (s != 1.0 && s != -1.0) throw std::invalid_argument("RC stick sign must be +1 or -1, got " + std::to_string(s));
}

std::uint16_t rc_pwm(const mavlink::RcChannels& rc, int i) {
  const std::array<std::uint16_t, 18> ch{rc.chan1_raw,  rc.chan2_raw,  rc.chan3_raw,  rc.chan4_raw,  rc.chan5_raw,  rc.chan6_raw,
                                         rc.chan7_raw,  rc.chan8_raw,  rc.chan9_raw,  rc.chan10_raw, rc.chan11_raw, rc.chan12_raw,
                                         rc.chan13_raw, rc.chan14_raw, rc.chan15_raw, rc.chan16_raw, rc.chan17_raw, rc.chan18_raw};
  if (i < 0 || i >= 18 || (i >= 8 && i >= rc.chancount) || ch[i] == 0xFFFF) return 0;
  return ch[i];
}

RcSticks from_rc(const mavlink::RcChannels& rc, const RcMap& map) {
  auto centred = [&](int ch) {
    const std::uint16_t p = rc_pwm(rc, ch);
    return p == 0 ? 0.0 : std::clamp((static_cast<double>(p) - 1500.0) / 500.0, -1.0, 1.0);
  };
  RcSticks s;
  s.roll = centred(map.stick_channel[0]) * map.sign[0];
  s.pitch = centred(map.stick_channel[1]) * map.sign[1];
  s.yaw = centred(map.stick_channel[2]) * map.sign[2];
  const std::uint16_t t = rc_pwm(rc, map.stick_channel[3]);
  s.throttle = t == 0 ? 0.0 : std::clamp((static_cast<double>(t) - 1000.0) / 1000.0, 0.0, 1.0);
  for (int i = 0; i < 4; ++i) s.aux[i] = centred(map.aux_channel[i]);
  return s;
}

}  // namespace tern::fcu
