// tern_fcu_serial/firmware.hpp: the ROSflight firmware's externally visible behaviour, as
// tern-fcu-emulator plays it and the tests pin it. Plain C++, no I/O, no tern host types.
//
// Source: rosflight/rosflight_firmware at the commit rosflight/rosflight_ros_pkgs pins
// (e8cf6a0f1381591eedfc6aef91f28a9c9ad45f98), read as the specification; no firmware code is
// copied. Each member says the firmware file and function it follows:
//   Params      src/param.cpp (Params::set_defaults, set_param_int/float, lookup_param_id)
//   arming      src/state_manager.cpp (StateManager::set_event, set_error, clear_error)
//   RC          src/rc.cpp (RC::run, check_rc_lost, look_for_arm_disarm_signal)
//   commands    src/command_manager.cpp (CommandManager::run, determine_override_status, do_muxing)
//   mixer       include/mixer.h (fixedwing_mixing, fixedwing_inverted_vtail_mixing), src/mixer.cpp
//               (Mixer::init_mixing, mix_fixedwing, mix_output)
//   sensors     src/sensors.cpp (init_imu, calibrate_gyro/accel/baro/diff_pressure, correct_*)
//
// Units: time in integer nanoseconds of the FCU's clock (since boot); RC channels as the
// board reads them, 0..1 = 1000..2000 us PWM (rc.cpp RC::fake_rx); accelerations m/s^2, rates
// rad/s, pressures Pa. Outputs: the 14 raw PWM fractions of Mixer::raw_outputs (servo
// 0.5 + 0.5 u, motor 0..1 and 0 while disarmed).
//
// Not emulated (the emulator says so in a STATUSTEXT when asked for it): multirotor mixers
// (PRIMARY_MIXER 0..8), custom mixers (11) and a SECONDARY_MIXER other than "same as primary",
// the attitude controller (fixed-wing pass-through only), temperature compensation, AUX commands.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tern::fcu::firmware {

/// The emulated pilot's default transmitter script (tern-fcu-emulator --rc, the plugin's
/// emulator_rc): arms a configured fixed wing (RC_ARM_CHN 4, RC_THR_OVRD_CHN 5, TAKE_MIN_THR 0)
/// at 2 s: throttle low, override switch on (required to arm without TAKE_MIN_THR:
/// state_manager.cpp StateManager::set_event), arm switch on, override switch off.
inline constexpr const char* kDefaultRcScript = "0 throttle=0 aux1=-1 aux2=-1; 2 aux2=1; 2.1 aux1=1; 2.5 aux2=-1";

/// The firmware's pressure altitude, m, of a static pressure in Pa (lib/turbomath turbomath::alt:
/// ISA, 101325 Pa at 0 m): SMALL_BARO's altitude and GROUND_LEVEL after the baro's calibration.
float pressure_altitude(float pressure);

/// MAV_PARAM_TYPE of a firmware parameter (param.cpp: PARAM_TYPE_INT32 / PARAM_TYPE_FLOAT).
enum class ParamType : std::uint8_t { int32 = 6, real32 = 9 };

struct Param {
  std::string name;  ///< at most 16 characters
  ParamType type = ParamType::real32;
  std::int32_t i = 0;  ///< value of an int32 parameter
  float f = 0.0f;      ///< value of a float parameter
};

/// The parameter table (the subset of param.cpp Params::set_defaults the emulator uses, with
/// the firmware's names, types and defaults).
class Params {
 public:
  Params();
  static std::vector<Param> defaults();
  std::size_t size() const { return table_.size(); }
  const Param& at(std::size_t i) const { return table_.at(i); }
  /// Index of `name` (Params::lookup_param_id), or nullopt.
  std::optional<std::size_t> find(std::string_view name) const;
  std::int32_t get_int(std::string_view name) const;  ///< throws std::out_of_range naming it
  float get_float(std::string_view name) const;
  /// Params::set_param_int/float: true (and the value changes) only when it differs; the
  /// caller then echoes PARAM_VALUE. Setting a parameter of the other type throws.
  bool set_int(std::string_view name, std::int32_t v);
  bool set_float(std::string_view name, float v);
  bool set_int(std::size_t i, std::int32_t v);
  bool set_float(std::size_t i, float v);
  /// ROSFLIGHT_CMD_SET_PARAM_DEFAULTS: every value back to its default (nothing is echoed).
  void set_defaults();
  /// Indices changed since the last call (each is echoed with a PARAM_VALUE).
  std::vector<std::size_t> take_changes();

 private:
  const Param& get(std::string_view name, ParamType t) const;
  std::size_t index(std::string_view name) const;
  std::vector<Param> table_;
  std::vector<std::size_t> changes_;
};

/// StateManager::ErrorCode bits (include/state_manager.h).
enum Error : std::uint16_t {
  kErrorInvalidMixer = 0x0001,
  kErrorImuNotResponding = 0x0002,
  kErrorRcLost = 0x0004,
  kErrorUnhealthyEstimator = 0x0008,
  kErrorTimeGoingBackwards = 0x0010,
  kErrorUncalibratedImu = 0x0020,
  kErrorBufferOverrun = 0x0040,
  kErrorInvalidFailsafe = 0x0080
};

/// CommandManager::RCOverrideReason bits (include/command_manager.h).
enum Override : std::uint16_t {
  kOverrideAttSwitch = 0x1,
  kOverrideThrSwitch = 0x2,
  kOverrideX = 0x4,
  kOverrideY = 0x8,
  kOverrideZ = 0x10,
  kOverrideT = 0x20,
  kOverrideOffboardXInactive = 0x40,
  kOverrideOffboardYInactive = 0x80,
  kOverrideOffboardZInactive = 0x100,
  kOverrideOffboardTInactive = 0x200
};

/// One receiver frame as the board hands it over (Board::rc_read into RcStruct).
struct RcFrame {
  std::array<float, 8> chan{};  ///< 0..1 = 1000..2000 us
  bool lost = false;            ///< frameLost | failsafeActivated (an SBUS receiver's failsafe flag)
};

/// One channel of the command muxer (command_manager.h control_channel_t), in the firmware's
/// order u[0..9] = Fx, Fy, Fz, Qx, Qy, Qz, then 4 pass-through channels.
struct Channel {
  bool active = false;
  float value = 0.0f;
};
using Control = std::array<Channel, 10>;

/// A STATUSTEXT the firmware would send (CommManager::log), severity as MAV_SEVERITY.
struct LogLine {
  std::uint8_t severity = 6;
  std::string text;
};

class Firmware {
 public:
  static constexpr int kOutputs = 14;  ///< Mixer::NUM_TOTAL_OUTPUTS

  /// Boots from `flash` (the stored parameters; nullopt: an empty or unreadable flash, whose
  /// defaults the firmware takes and says so: param.cpp Params::init): StateManager::init,
  /// Mixer::init_mixing, Sensors::init_imu and CommandManager::init_failsafe set their errors;
  /// disarmed.
  explicit Firmware(std::optional<Params> flash = Params{});

  // ---- inputs (the main loop of src/rosflight.cpp ROSflight::run) ----
  /// OFFBOARD_CONTROL (mavlink_adapter.cpp handle_msg_offboard_control; comm_manager.cpp
  /// offboard_control_callback): a mode other than 0..2 is dropped; ignore bits (IGNORE_VALUE0..9)
  /// clear `active`. u[0..9] = Fx Fy Fz Qx Qy Qz + 4 pass-through, as sent (pass-through: servo
  /// -1..1, motor 0..1; clamped only by the mixer); stamped in whole ms of `now`.
  void offboard(std::uint8_t mode, const std::array<float, 10>& u, std::uint16_t ignore, std::int64_t now);
  /// A receiver frame: RC::run, then CommandManager::run (muxing happens only here).
  void rc(const RcFrame& f, std::int64_t now);
  /// One IMU sample: Sensors::run (calibration, bias correction), then the loop body:
  /// CommandManager::run (failsafe), Mixer::mix_output, except on the first sample after boot
  /// (ROSflight::check_time_going_forwards only notes its time). Returns the corrected sample.
  void imu(std::array<float, 3>& accel, std::array<float, 3>& gyro, std::int64_t now);
  /// Sensors::correct_baro: calibrates at boot; the pressure is reported unchanged.
  void baro(float pressure, std::int64_t now);
  /// Sensors::correct_diff_pressure: calibrates at boot, then subtracts DIFF_PRESS_BIAS.
  float diff_pressure(float pressure, std::int64_t now);

  // ---- commands (comm_manager.cpp CommManager::command_callback, refused while armed) ----
  bool start_imu_calibration();
  bool start_gyro_calibration();
  bool start_baro_calibration();
  bool start_airspeed_calibration();
  /// After a parameter changed (the firmware's param_change_callback listeners).
  void param_changed(std::string_view name);

  // ---- what the FCU reports ----
  bool armed() const { return armed_; }
  bool failsafe() const { return failsafe_; }
  std::uint16_t error_codes() const { return errors_; }
  std::uint16_t rc_override() const { return rc_override_; }
  bool offboard_active() const;
  const std::array<float, kOutputs>& raw_outputs() const { return raw_; }
  Params& params() { return params_; }
  const Params& params() const { return params_; }
  /// STATUSTEXT lines and parameter echoes queued since the last call.
  std::vector<LogLine> take_log();
  /// True once after a change the firmware reports with an extra ROSFLIGHT_STATUS
  /// (CommManager::update_status).
  bool take_status_request();

 private:
  enum class Fsm { init, preflight, armed, error, failsafe, calibrating };
  enum class Event { initialized, rc_lost, rc_found, request_arm, request_disarm, error, no_error, cal_done, cal_failed };
  // state (firmware_state.cpp)
  void set_error(std::uint16_t e);
  void clear_error(std::uint16_t e);
  void set_event(Event e, std::int64_t now);
  void process_errors(std::int64_t now);
  void refuse_arm(std::int64_t now);
  void init_failsafe();
  // RC and commands (firmware_command.cpp)
  bool rc_run(const RcFrame& f, std::int64_t now);
  void arm_disarm_signal(std::int64_t now);
  bool switch_on(std::string_view channel_param) const;
  void log_switches();
  void command_run(bool new_rc, std::int64_t now);
  std::uint16_t override_status(std::int64_t now);
  bool stick_deviated(int mux, std::int64_t now);
  // mixer (firmware_mixer.cpp)
  void init_mixing();
  void mix_output();
  // sensors (firmware_sensors.cpp)
  void check_imu_calibrated();
  void calibrate_imu(const std::array<float, 3>& accel, const std::array<float, 3>& gyro);
  void log(std::uint8_t severity, std::string text);

  Params params_;
  Fsm fsm_ = Fsm::init;
  bool armed_ = false, failsafe_ = false, error_ = false, status_request_ = false;
  std::uint16_t errors_ = 0, rc_override_ = 0;
  std::int64_t next_arm_error_ms_ = 0;  ///< StateManager::next_arming_error_msg_ms_
  // RC
  RcFrame rc_frame_;
  std::array<float, 4> stick_{};  ///< X, Y, Z (-1..1), F (0..1): rc.cpp RC::Stick
  std::int64_t arm_sticks_since_ = 0, prev_rc_time_ = 0;
  // commands
  Control rc_cmd_{}, offboard_cmd_{}, combined_{};
  std::int64_t offboard_stamp_ = 0;
  std::array<std::int64_t, 6> last_override_{};  ///< per mux channel, CommandManager::stick_deviated
  // mixer
  bool mixer_valid_ = false;
  std::array<std::array<float, 10>, 10> mix_{};  ///< mix_[input][output]
  std::array<char, 10> output_type_{};           ///< 'S' servo, 'M' motor, 'A' aux
  std::array<float, kOutputs> raw_{};
  // sensors
  struct Cal {  ///< a ground calibration in progress (Sensors::calibrate_baro/diff_pressure)
    int count = 0;
    double mean = 0, var = 0;
    std::int64_t last = 0;
  };
  Cal baro_cal_, diff_cal_;
  bool baro_calibrated_ = false, diff_calibrated_ = false;
  bool gyro_cal_ = false, acc_cal_ = false, imu_seen_ = false;
  int imu_cal_count_ = 0, gyro_cal_count_ = 0;
  std::array<double, 3> acc_sum_{}, gyro_sum_{}, acc_max_{}, acc_min_{};
  std::vector<LogLine> log_;
};

}  // namespace tern::fcu::firmware
