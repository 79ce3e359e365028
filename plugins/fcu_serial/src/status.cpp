// status.cpp: see tern_fcu_serial/status.hpp.
#include "tern_fcu_serial/status.hpp"

#include <utility>

namespace tern::fcu {

namespace {
std::string join(const std::string& a, const std::string& b) { return a.empty() ? b : a + "; " + b; }
}  // namespace

std::string describe_errors(std::uint16_t e) {
  const std::pair<std::uint16_t, const char*> words[] = {
      {0x01, "invalid mixer: set PRIMARY_MIXER (fixed wing: 9, inverted V-tail: 10) with `tern fcu param set`"},
      {0x02, "IMU not responding"},
      {0x04, "RC lost: is the transmitter on and bound?"},
      {0x08, "unhealthy estimator"},
      {0x10, "time going backwards"},
      {0x20, "IMU not calibrated: run `tern fcu calibrate imu` (aircraft level and still)"},
      {0x40, "buffer overrun"},
      {0x80, "invalid failsafe setting (FAILSAFE_THR)"}};
  std::string s;
  for (const auto& [bit, text] : words)
    if (e & bit) s = join(s, text);
  return s;
}

std::string arming_problems(bool armed, std::uint16_t e) {
  std::string s = armed ? "" : "FCU disarmed: arm from the transmitter";
  if (e) s = join(s, describe_errors(e));
  return s;
}

std::string describe_override(std::uint16_t o) {
  const std::pair<std::uint16_t, const char*> words[] = {{0x001, "attitude override switch"},
                                                         {0x002, "throttle override switch"},
                                                         {0x004, "roll stick"},
                                                         {0x008, "pitch stick"},
                                                         {0x010, "yaw stick"},
                                                         {0x020, "RC throttle below tern's (TAKE_MIN_THR)"},
                                                         {0x040, "no tern roll (Qx) command"},
                                                         {0x080, "no tern pitch (Qy) command"},
                                                         {0x100, "no tern yaw (Qz) command"},
                                                         {0x200, "no tern throttle command"}};
  std::string s;
  for (const auto& [bit, text] : words)
    if (o & bit) s = join(s, text);
  return s;
}

std::uint8_t fix_type(std::uint8_t f) {
  switch (f) {
    case 1: return 1;   // GNSS_FIX_TYPE_DEAD_RECKONING_ONLY
    case 2: return 2;   // GNSS_FIX_TYPE_2D_FIX
    case 3:             // GNSS_FIX_TYPE_3D_FIX
    case 4:             // GNSS_FIX_TYPE_GNSS_PLUS_DEAD_RECKONING
    case 6:             // GNSS_FIX_RTK_FLOAT
    case 7: return 3;   // GNSS_FIX_RTK_FIXED
    default: return 0;  // no fix, 5 GNSS_FIX_TYPE_TIME_FIX_ONLY, unknown
  }
}

}  // namespace tern::fcu
