// tern_fcu_serial/fcu_side.hpp: the FCU's side of ROSflight's companion protocol, as
// tern-fcu-emulator and the tests play it, in front of the emulated firmware (firmware.hpp).
// Plain C++, no tern host types, no I/O: handle() takes a received frame, stream() the
// frames the firmware sends on its own; both append frames to a byte buffer.
//
// Follows (rosflight_firmware, the commit rosflight_ros_pkgs pins):
//   src/mavlink_adapter.cpp  MavlinkAdapter: component id 250 (MAV_COMP_ID_ROSFLIGHT_FIRMWARE)
//                            except PARAM_VALUE (component 0), one sequence counter; PARAM_SET
//                            of a type other than INT32/REAL32 dropped; an unknown ROSFLIGHT_CMD
//                            acknowledged as failed under the sender's system id.
//   src/comm_manager.cpp     CommManager: requests whose target_system is not SYS_ID ignored;
//                            PARAM_SET applied only to a parameter of the same type; PARAM_VALUE
//                            echoed only when a value changes; PARAM_REQUEST_LIST answered one
//                            parameter per loop (send_next_param); every ROSFLIGHT_CMD refused
//                            while armed (command_callback); TIMESYNC answered with
//                            clock_micros() * 1000; STATUSTEXT held until a HEARTBEAT arrived,
//                            then sent one a loop with clock_micros() as the system id
//                            (send_buffered_log_messages), later ones at once as SYS_ID.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tern_fcu_serial/codec.hpp"
#include "tern_fcu_serial/firmware.hpp"

namespace tern::fcu {

/// ROSFLIGHT_CMD values (rosflight.xml enum ROSFLIGHT_CMD).
enum class RosflightCmd : std::uint8_t {
  rc_calibration = 0,
  accel_calibration = 1,
  gyro_calibration = 2,
  baro_calibration = 3,
  airspeed_calibration = 4,
  read_params = 5,
  write_params = 6,
  set_param_defaults = 7,
  reboot = 8,
  reboot_to_bootloader = 9,
  send_version = 10,
  reset_origin = 11,
  send_all_config_infos = 12
};

/// MAV_PARAM_TYPE values used by ROSflight.
inline constexpr std::uint8_t kParamInt32 = 6;
inline constexpr std::uint8_t kParamReal32 = 9;
/// MAV_COMP_ID_ROSFLIGHT_FIRMWARE (rosflight.xml): the FCU's component id.
inline constexpr std::uint8_t kFirmwareComponent = 250;

/// A PARAM_VALUE/PARAM_SET float read as the number it stands for (int32 types bit for bit).
double param_number(float wire, std::uint8_t type);
/// The float to send for number v of the given type.
float param_wire(double v, std::uint8_t type);

class FcuSide {
 public:
  /// flash: the stored parameters (nullopt: none readable; the firmware boots with its defaults
  /// and writes them).
  FcuSide(std::optional<firmware::Params> flash, std::string version);

  /// Handles one frame from the companion at FCU time fcu_ns; answers go to `out`.
  void handle(const mavlink::Frame& f, std::int64_t fcu_ns, std::vector<std::uint8_t>& out);
  /// The end of one firmware loop at FCU time fcu_ns (CommManager::stream): parameter echoes, a
  /// status the firmware asked for, the next parameter of a list request, log lines.
  void stream(std::int64_t fcu_ns, std::vector<std::uint8_t>& out);
  /// Appends a frame the firmware sends as itself (system SYS_ID, component 250).
  template <class T>
  void send(const T& m, std::vector<std::uint8_t>& out) {
    enc_.append_as(m, out, sysid(), kFirmwareComponent);
  }
  mavlink::RosflightStatus status() const;  ///< CommManager::send_status
  /// The duration of the last control loop, reported in the status (ROSflight::get_loop_time_us).
  void set_loop_time_us(std::uint16_t us) { loop_time_us_ = us; }
  mavlink::Heartbeat heartbeat() const;  ///< MavlinkAdapter::send_heartbeat

  firmware::Firmware& fw() { return fw_; }
  const firmware::Firmware& fw() const { return fw_; }
  std::uint8_t sysid() const { return static_cast<std::uint8_t>(fw_.params().get_int("SYS_ID")); }
  std::uint64_t commands() const { return commands_; }  ///< OFFBOARD_CONTROL frames received
  bool reboot_requested() const { return reboot_; }
  void clear_reboot() { reboot_ = false; }
  std::uint64_t writes() const { return writes_; }            ///< WRITE_PARAMS commands carried out
  const firmware::Params& stored() const { return stored_; }  ///< what WRITE_PARAMS saved

 private:
  static constexpr std::size_t kLogBufferSize = 25;  ///< CommManager::LogMessageBuffer::LOG_BUF_SIZE
  void send_param(std::size_t i, std::vector<std::uint8_t>& out);
  void send_log(const firmware::LogLine& line, std::uint8_t system_id, std::vector<std::uint8_t>& out);
  void stream_echoes(std::vector<std::uint8_t>& out);
  void param_set(const mavlink::ParamSet& s);
  void command(const mavlink::RosflightCmd& c, std::uint8_t from_sysid, std::vector<std::uint8_t>& out);
  firmware::Firmware fw_;
  firmware::Params stored_;
  std::string version_;
  mavlink::Encoder enc_{1, kFirmwareComponent};
  std::size_t list_next_ = SIZE_MAX;
  std::vector<firmware::LogLine> held_log_;
  std::uint16_t loop_time_us_ = 0;
  bool connected_ = false, reboot_ = false;
  std::uint64_t commands_ = 0, writes_ = 0;
};

}  // namespace tern::fcu
