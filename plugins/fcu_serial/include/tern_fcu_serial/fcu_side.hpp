// tern_fcu_serial/fcu_side.hpp: the FCU's side of ROSflight's companion protocol, as the FCU
// emulator (tools/tern_fcu_emulator.cpp) and the tests play it: parameters (PARAM_REQUEST_LIST,
// PARAM_REQUEST_READ, PARAM_SET -> PARAM_VALUE), commands (ROSFLIGHT_CMD -> ROSFLIGHT_CMD_ACK,
// ROSFLIGHT_VERSION for SEND_VERSION), TIMESYNC answers, and the latest OFFBOARD_CONTROL.
// Plain C++, no tern host types, no I/O: handle() takes a received frame and appends the
// answer frames to a byte buffer.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tern_fcu_serial/codec.hpp"

namespace tern::fcu {

/// ROSFLIGHT_CMD values (rosflight.xml enum ROSFLIGHT_CMD).
enum class RosflightCmd : std::uint8_t {
  rc_calibration = 0, accel_calibration = 1, gyro_calibration = 2, baro_calibration = 3,
  airspeed_calibration = 4, read_params = 5, write_params = 6, set_param_defaults = 7, reboot = 8,
  reboot_to_bootloader = 9, send_version = 10, reset_origin = 11, send_all_config_infos = 12
};

/// MAV_PARAM_TYPE values used by ROSflight.
inline constexpr std::uint8_t kParamInt32 = 6;
inline constexpr std::uint8_t kParamReal32 = 9;

struct FcuParam {
  std::string name;  ///< at most 16 characters
  float value = 0;   ///< MAVLink carries every value as a float; an int32 is stored bit for bit
  std::uint8_t type = kParamReal32;
};

/// A PARAM_VALUE/PARAM_SET float read as the number it stands for (int32 types bit for bit).
double param_number(float wire, std::uint8_t type);
/// The float to send for number v of the given type.
float param_wire(double v, std::uint8_t type);

class FcuSide {
 public:
  /// `params`: the FCU's parameter table (e.g. ROSflight's fixed-wing defaults).
  FcuSide(std::vector<FcuParam> params, std::string version, std::uint8_t sysid = 1, std::uint8_t compid = 1);

  /// ROSflight's fixed-wing parameters of fixedwing_firmware.yaml plus the few the emulator uses.
  static std::vector<FcuParam> default_params();

  /// Handles one frame from the companion at FCU time fcu_ns; answers go to `out`.
  void handle(const mavlink::Frame& f, std::int64_t fcu_ns, std::vector<std::uint8_t>& out);

  mavlink::Encoder& encoder() { return enc_; }
  const std::vector<FcuParam>& params() const { return params_; }
  /// Latest OFFBOARD_CONTROL and how many have arrived.
  const mavlink::OffboardControl& command() const { return cmd_; }
  std::uint64_t commands() const { return commands_; }
  std::int64_t last_command_ns() const { return last_cmd_ns_; }
  bool reboot_requested() const { return reboot_; }
  void clear_reboot() { reboot_ = false; }
  std::uint64_t writes() const { return writes_; }  ///< WRITE_PARAMS commands

 private:
  void send_param(std::size_t i, std::vector<std::uint8_t>& out);
  std::vector<FcuParam> params_, defaults_;
  std::string version_;
  mavlink::Encoder enc_;
  mavlink::OffboardControl cmd_;
  std::uint64_t commands_ = 0, writes_ = 0;
  std::int64_t last_cmd_ns_ = -1;
  bool reboot_ = false;
};

}  // namespace tern::fcu
