// firmware_command.cpp: RC input, arming from the transmitter, and the command muxer of the
// emulated firmware, after src/rc.cpp (RC) and src/command_manager.cpp (CommandManager).
// Fixed-wing only (FIXED_WING = 1: every channel pass-through). See firmware.hpp.
#include <cmath>

#include "tern_fcu_serial/firmware.hpp"

namespace tern::fcu::firmware {

namespace {
constexpr int kStickX = 0, kStickY = 1, kStickZ = 2, kStickF = 3;  // rc.h RC::Stick
constexpr int kMuxQx = 3;                                          // command_manager.h MuxChannel
constexpr std::int64_t kMs = 1'000'000;
// CommandManager::X/Y/Z/T_OVERRIDDEN: the reasons that hand a channel to the pilot.
constexpr std::uint16_t kX = kOverrideAttSwitch | kOverrideX | kOverrideOffboardXInactive;
constexpr std::uint16_t kY = kOverrideAttSwitch | kOverrideY | kOverrideOffboardYInactive;
constexpr std::uint16_t kZ = kOverrideAttSwitch | kOverrideZ | kOverrideOffboardZInactive;
constexpr std::uint16_t kT = kOverrideThrSwitch | kOverrideT | kOverrideOffboardTInactive;
}  // namespace

// comm_manager.cpp offboard_control_callback: values and active flags, stamped in ms; the
// mode only sets control types, which a fixed wing ignores (pass-through everywhere).
void Firmware::offboard(std::uint8_t mode, const std::array<float, 10>& u, std::uint16_t ignore, std::int64_t now) {
  if (mode > 2) return;  // mavlink_adapter.cpp handle_msg_offboard_control: invalid mode dropped
  for (int i = 0; i < 10; ++i) offboard_cmd_[i] = {!(ignore & (1u << i)), u[i]};
  offboard_stamp_ = now / kMs * kMs;
}

// RC::switch_mapped / switch_on: a switch on channel 4..RC_NUM_CHN-1, on at >= 0.8 (or < 0.2
// with SWITCH_n_DIR -1).
bool Firmware::switch_on(std::string_view channel_param) const {
  const std::int32_t ch = params_.get_int(channel_param);
  if (ch <= 3 || ch >= params_.get_int("RC_NUM_CHN") || ch >= 8) return false;
  const std::int32_t dir = ch <= 7 ? params_.get_int("SWITCH_" + std::to_string(ch + 1) + "_DIR") : 1;
  const float pwm = rc_frame_.chan[static_cast<std::size_t>(ch)];
  return dir < 0 ? pwm < 0.2f : pwm >= 0.8f;
}

// RC::init_switches (at boot and when a switch's channel or direction changes): one line per
// switch, mapped when its channel is 4..RC_NUM_CHN-1.
void Firmware::log_switches() {
  const std::pair<const char*, const char*> sw[] = {{"ARM", "RC_ARM_CHN"},
                                                    {"ATTITUDE OVERRIDE", "RC_ATT_OVRD_CHN"},
                                                    {"THROTTLE OVERRIDE", "RC_THR_OVRD_CHN"},
                                                    {"ATTITUDE TYPE", "RC_ATT_CTRL_CHN"}};
  for (const auto& [name, param] : sw) {
    const std::int32_t ch = params_.get_int(param);
    if (ch > 3 && ch < params_.get_int("RC_NUM_CHN"))
      log(6, std::string(name) + " switch mapped to RC channel " + std::to_string(ch));
    else
      log(6, std::string(name) + " switch not mapped");
  }
}

// RC::look_for_arm_disarm_signal: the arm switch if mapped, else throttle low and yaw right
// (arm) or left (disarm) held for more than 1 s.
void Firmware::arm_disarm_signal(std::int64_t now) {
  const std::int64_t dt = now - prev_rc_time_;
  prev_rc_time_ = now;
  const std::int32_t arm_ch = params_.get_int("RC_ARM_CHN");
  if (arm_ch > 3 && arm_ch < params_.get_int("RC_NUM_CHN")) {
    if (switch_on("RC_ARM_CHN")) {
      if (!armed_) set_event(Event::request_arm, now);
    } else {
      set_event(Event::request_disarm, now);
    }
    return;
  }
  const float th = params_.get_float("RC_ARM_THRESHOLD");
  const bool low = stick_[kStickF] < th;
  const bool pose = armed_ ? low && stick_[kStickZ] < -(1.0f - th) : low && stick_[kStickZ] > 1.0f - th;
  arm_sticks_since_ = pose ? arm_sticks_since_ + dt : 0;
  if (arm_sticks_since_ > 1000 * kMs) {
    const bool disarm = armed_;
    set_event(disarm ? Event::request_disarm : Event::request_arm, now);
    if (disarm) arm_sticks_since_ = 0;  // only after a disarm request, as rc.cpp does
  }
}

// RC::run: lost frame or a channel outside -0.25..1.25 -> EVENT_RC_LOST (no new command);
// otherwise sticks (X, Y, Z: 2 (pwm - 0.5), F: pwm), switches, arming.
bool Firmware::rc_run(const RcFrame& f, std::int64_t now) {
  rc_frame_ = f;
  bool lost = f.lost;
  for (int i = 0; i < params_.get_int("RC_NUM_CHN") && i < 8; ++i)
    lost = lost || f.chan[static_cast<std::size_t>(i)] < -0.25f || f.chan[static_cast<std::size_t>(i)] > 1.25f;
  set_event(lost ? Event::rc_lost : Event::rc_found, now);
  if (lost) return false;
  const char* chn[] = {"RC_X_CHN", "RC_Y_CHN", "RC_Z_CHN", "RC_F_CHN"};
  for (int s = 0; s < 4; ++s) {
    const float pwm = f.chan[static_cast<std::size_t>(params_.get_int(chn[s]) & 7)];
    stick_[static_cast<std::size_t>(s)] = s == kStickF ? pwm : 2.0f * (pwm - 0.5f);
  }
  arm_disarm_signal(now);
  return true;
}

void Firmware::rc(const RcFrame& f, std::int64_t now) {
  const bool fresh = rc_run(f, now);
  command_run(fresh, now);
}

// CommandManager::stick_deviated: beyond RC_OVRD_DEV, and for RC_OVRD_LAG_T ms after.
bool Firmware::stick_deviated(int mux, std::int64_t now) {
  const std::int64_t ms = now / kMs;
  std::int64_t& last = last_override_[static_cast<std::size_t>(mux)];
  if (ms < last + params_.get_int("RC_OVRD_LAG_T")) return true;
  if (std::fabs(stick_[static_cast<std::size_t>(mux - kMuxQx)]) > params_.get_float("RC_OVRD_DEV")) {
    last = ms;
    return true;
  }
  return false;
}

// CommandManager::determine_override_status: switches, deviated sticks, inactive offboard
// channels (ignored or timed out) and, with TAKE_MIN_THR, an RC throttle below tern's.
std::uint16_t Firmware::override_status(std::int64_t now) {
  std::uint16_t o = 0;
  if (switch_on("RC_ATT_OVRD_CHN")) o |= kOverrideAttSwitch;
  if (switch_on("RC_THR_OVRD_CHN")) o |= kOverrideThrSwitch;
  const std::uint16_t stick_bit[] = {kOverrideX, kOverrideY, kOverrideZ};
  const std::uint16_t inactive_bit[] = {kOverrideOffboardXInactive, kOverrideOffboardYInactive, kOverrideOffboardZInactive};
  for (int i = 0; i < 3; ++i) {
    if (stick_deviated(kMuxQx + i, now)) o |= stick_bit[i];
    if (!offboard_cmd_[static_cast<std::size_t>(kMuxQx + i)].active) o |= inactive_bit[i];
  }
  const std::int32_t axis = params_.get_int("RC_F_AXIS");
  const std::size_t f = axis >= 0 && axis <= 2 ? static_cast<std::size_t>(axis) : 2;  // invalid: Z
  if (!offboard_cmd_[f].active) o |= kOverrideOffboardTInactive;
  if (params_.get_int("TAKE_MIN_THR") && rc_cmd_[f].value < offboard_cmd_[f].value) o |= kOverrideT;
  return o;
}

// CommandManager::run: failsafe command while in failsafe; otherwise only on a new RC command:
// interpret_rc (fixed wing: u[3..5] = sticks X, Y, Z, u[RC_F_AXIS] = stick F), offboard
// timeout (OFFBOARD_TIMEOUT ms), override status, muxing channel by channel.
void Firmware::command_run(bool new_rc, std::int64_t now) {
  const std::uint16_t before = rc_override_;
  if (failsafe_) {
    // fixedwing_failsafe_command_: u[0..5] active at 0 (throttle 0, surfaces neutral)
    for (int i = 0; i < 10; ++i) combined_[static_cast<std::size_t>(i)] = {i < 6, 0.0f};
  } else if (new_rc) {
    for (auto& c : rc_cmd_) c.value = 0.0f;
    rc_cmd_[3].value = stick_[kStickX];
    rc_cmd_[4].value = stick_[kStickY];
    rc_cmd_[5].value = stick_[kStickZ];
    const std::int32_t axis = params_.get_int("RC_F_AXIS");
    rc_cmd_[axis >= 0 && axis <= 2 ? static_cast<std::size_t>(axis) : 2].value = stick_[kStickF];
    if (now / kMs > offboard_stamp_ / kMs + params_.get_int("OFFBOARD_TIMEOUT"))
      for (auto& c : offboard_cmd_) c.active = false;
    rc_override_ = override_status(now);
    const std::uint16_t mask[] = {kT, kT, kT, kX, kY, kZ};
    for (std::size_t i = 0; i < 6; ++i) combined_[i] = (rc_override_ & mask[i]) ? rc_cmd_[i] : offboard_cmd_[i];
    for (std::size_t i = 6; i < 10; ++i) combined_[i] = offboard_cmd_[i];
  }
  if (before != rc_override_) status_request_ = true;
}

bool Firmware::offboard_active() const {
  for (std::size_t i = 0; i < 6; ++i)
    if (offboard_cmd_[i].active) return true;
  return false;
}

}  // namespace tern::fcu::firmware
