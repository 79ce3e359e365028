// plugin_params.cpp: fcu_serial's ports and parameters, and the channel mappings they make
// (see fcu_serial_plugin.hpp, README.md).
#include <cmath>
#include <filesystem>
#include <sstream>

#include <spdlog/spdlog.h>

#include "fcu_serial_plugin.hpp"
#include "tern/aircraft.hpp"
#include "tern_fcu_serial/firmware.hpp"

namespace tern::fcu_serial {

using tern::ParamError;
using tern::ParamSpec;

namespace {
constexpr double kDefaultMaxDeflection = 0.785398;  // rad (45 deg): no aircraft file, no parameter
}  // namespace

void FcuSerial::configure() {
  declare_ports();
  declare_link_params();
  declare_mapping_params();
  (void)tern::period_from_hz(command_rate_());
  take_start_params();
  if (!context().describing() && max_deflection_().empty())
    log().info("pass-through scaling: max deflection a {:.4f}, e {:.4f}, r {:.4f} rad", map_.max_deflection[0], map_.max_deflection[1],
               map_.max_deflection[2]);
}

void FcuSerial::take_start_params() {
  try {
    policy_ = fcu::parse_clock_policy(clock_name_());
  } catch (const std::invalid_argument& e) {
    throw ParamError("parameter '" + qname("clock") + "': " + e.what());
  }
  map_ = actuator_map(default_max_deflection());
  rc_map_ = rc_map();
  if (!context().describing() && max_deflection_().empty()) map_ = actuator_map(aircraft_max_deflection());
}

void FcuSerial::declare_ports() {
  declare(actuators_in_, "actuators", "surface deflections (rad) and throttle (0..1) sent to the FCU", tern::Need::optional);
  declare(imu_out_, "imu", "FCU accelerometer (m/s^2) and gyro (rad/s), FRD body axes (SMALL_IMU)");
  declare(gnss_out_, "gnss", "FCU GNSS receiver: deg, m MSL, NED m/s (ROSFLIGHT_GNSS)");
  declare(baro_out_, "baro", "FCU barometer: Pa, K (SMALL_BARO)");
  declare(diff_out_, "diff_pressure", "FCU pitot differential pressure: Pa, after its boot calibration (DIFF_PRESSURE)");
  declare(mag_out_, "mag", "FCU magnetometer: T, body axes (SMALL_MAG)");
  declare(rc_out_, "rc", "RC receiver as the FCU reports it (RC_CHANNELS), with override and failsafe");
  declare(status_out_, "fcu_status", "FCU status (ROSFLIGHT_STATUS)");
}

void FcuSerial::declare_link_params() {
  declare(transport_, "transport", "serial",
          ParamSpec("", 0, 0, "link to the FCU: serial port or UDP (ROSflight SIL)").one_of({"serial", "udp"}).start_only());
  declare(device_, "device", "/dev/ttyACM0", ParamSpec("", 0, 0, "serial device of the FCU").start_only());
  declare(baud_, "baud", std::int64_t{921600}, ParamSpec("baud", 9600, 4000000, "serial baud rate").start_only());
  declare(udp_host_, "udp_host", "127.0.0.1", ParamSpec("", 0, 0, "IP address of both UDP ends").start_only());
  declare(udp_bind_port_, "udp_bind_port", std::int64_t{14520}, ParamSpec("", 1, 65535, "our UDP port (rosflight_io: 14520)").start_only());
  declare(udp_remote_port_, "udp_remote_port", std::int64_t{14525},
          ParamSpec("", 1, 65535, "the FCU's UDP port (ROSflight SIL: 14525)").start_only());
  declare(clock_name_, "clock", "fcu",
          ParamSpec("", 0, 0, "time source: the FCU's IMU stamps pace the flight, or the wall clock (TIMESYNC)")
              .one_of({"fcu", "wall"})
              .start_only());
  declare(
      lockstep_, "lockstep", false,
      ParamSpec("", 0, 0, "one OFFBOARD_CONTROL per IMU sample, before waiting for the next (tern-fcu-emulator --lockstep)").start_only());
  declare(connect_timeout_, "connect_timeout", 5.0,
          ParamSpec("s", 0.1, 120, "start() fails without an IMU sample within this time").start_only());
  declare(wait_timeout_, "wait_timeout", 0.25, ParamSpec("s", 0, 10, "clock fcu: longest wait of one step for the FCU's sample"));
  declare(link_timeout_, "link_timeout", 0.5, ParamSpec("s", 0.01, 60, "no frame for this long: link lost (reported)"));
  // OFFBOARD_TIMEOUT (param.cpp, int32 ms, default 100): CommandManager::run hands every channel
  // back to RC when the last OFFBOARD_CONTROL is older
  declare(command_rate_, "command_rate", 100.0,
          ParamSpec("Hz", 50, 1000,
                    "least rate of OFFBOARD_CONTROL (the firmware's OFFBOARD_TIMEOUT, 100 ms by default, hands the FCU to RC)"));
  declare(heartbeat_rate_, "heartbeat_rate", 1.0, ParamSpec("Hz", 0.1, 50, "rate of our HEARTBEAT"));
  declare(timesync_rate_, "timesync_rate", 10.0, ParamSpec("Hz", 0.1, 100, "rate of TIMESYNC requests"));
  declare(system_id_, "system_id", std::int64_t{1}, ParamSpec("", 1, 255, "our MAVLink system id").start_only());
  declare(component_id_, "component_id", std::int64_t{50},
          ParamSpec("", 0, 255, "our MAVLink component id (rosflight_io: 50)").start_only());
  declare(emulator_, "emulator", false,
          ParamSpec("", 0, 0, "start tern-fcu-emulator (sim_aero's aircraft behind a pseudo-terminal) and fly through it").start_only());
  declare(emulator_args_, "emulator_args", "",
          ParamSpec("", 0, 0, "extra arguments of tern-fcu-emulator, e.g. \"--wind 3.5,-3.5,0 --turbulence light\"").start_only());
  declare(
      emulator_params_, "emulator_params", "",
      ParamSpec("", 0, 0, "the emulated FCU's stored parameters (YAML NAME: value, relative to the mission file); empty: firmware defaults")
          .start_only());
  declare(emulator_rc_, "emulator_rc", fcu::firmware::kDefaultRcScript,
          ParamSpec("", 0, 0, "the emulated pilot's transmitter over time (tern-fcu-emulator --rc), or none").start_only());
  declare(emulator_firmware_, "emulator_firmware", "emulated",
          ParamSpec("", 0, 0,
                    "emulated: tern-fcu-emulator (tern's reading of the firmware); rosflight: tern-fcu-sil (the real ROSflight "
                    "firmware on tern's SIL board)")
              .one_of({"emulated", "rosflight"})
              .start_only());
  declare(emulator_link_, "emulator_link", "socket",
          ParamSpec("", 0, 0,
                    "the byte stream to the emulator: socket (a connected local stream socket, 3x faster in lockstep) or pty "
                    "(a pseudo-terminal: the terminal layer a USB serial FCU goes through)")
              .one_of({"socket", "pty"})
              .start_only());
  declare(calibrate_, "calibrate", "",
          ParamSpec("", 0, 0,
                    "a calibration the FCU runs at the start (ROSFLIGHT_CMD, as `tern fcu calibrate`): imu (accelerometer and gyro, "
                    "aircraft level and still), gyro, baro, airspeed (pitot covered); empty: none")
              .one_of({"", "imu", "gyro", "baro", "airspeed"})
              .start_only());
  declare(emulator_path_, "emulator_path", "",
          ParamSpec("", 0, 0, "the emulator's executable; empty: next to the tern command, then PATH").start_only());
}

void FcuSerial::declare_mapping_params() {
  declare(
      max_deflection_, "max_deflection", std::vector<double>{},
      ParamSpec("rad", 0.01, 3.2,
                "aileron, elevator, rudder deflection at full pass-through command; empty: the aircraft file's servos limits (else 45 deg)")
          .start_only());
  declare(channels_, "channels", "Qx Qy Qz Fx",
          ParamSpec("", 0, 0,
                    "the firmware's channel (Fx Fy Fz Qx Qy Qz) of aileron, elevator, rudder, throttle: "
                    "its fixed-wing mixer routes Qx Qy Qz to the aileron, elevator, rudder servos and Fx to the motor")
              .start_only());
  declare(signs_, "signs", std::vector<double>{1, 1, 1, 1},
          ParamSpec("", -1, 1, "+1 or -1 per aileron, elevator, rudder, throttle").of_size(4).start_only());
  declare(rc_channels_, "rc_channels", std::vector<double>{0, 1, 3, 2},
          ParamSpec("", 0, 17, "RC channel (0-based) of roll, pitch, yaw, throttle (ROSflight AETR)").of_size(4).start_only());
  declare(rc_aux_channels_, "rc_aux_channels", std::vector<double>{4, 5, 6, 7},
          ParamSpec("", 0, 17, "RC channels of aux[0..3]").of_size(4).start_only());
  declare(rc_signs_, "rc_signs", std::vector<double>{1, 1, 1},
          ParamSpec("", -1, 1, "+1 or -1 per roll, pitch, yaw stick").of_size(3).start_only());
  declare(mag_scale_, "mag_scale", 1.0, ParamSpec("T", 1e-12, 1, "tesla per unit of SMALL_MAG (1: the FCU reports T)"));
}

std::string FcuSerial::qname(const std::string& p) const { return context().instance_name() + "." + p; }

std::array<double, 3> FcuSerial::default_max_deflection() const {
  const auto& v = max_deflection_();
  if (v.empty()) return {kDefaultMaxDeflection, kDefaultMaxDeflection, kDefaultMaxDeflection};
  if (v.size() != 3)
    throw ParamError("parameter '" + qname("max_deflection") + "': needs 3 values [aileron, elevator, rudder], got " +
                     std::to_string(v.size()));
  return {v[0], v[1], v[2]};
}

std::array<double, 3> FcuSerial::aircraft_max_deflection() const {
  const std::filesystem::path f = context().aircraft_file();
  if (f.empty()) return {kDefaultMaxDeflection, kDefaultMaxDeflection, kDefaultMaxDeflection};
  // tern or ROSflight format, validated (tern/aircraft.hpp): an error names the file, field and value.
  const tern::Aircraft ac = tern::load_aircraft(f.string());
  return {ac.max_delta_a, ac.max_delta_e, ac.max_delta_r};
}

fcu::ActuatorMap FcuSerial::actuator_map(std::array<double, 3> max_deflection) const {
  fcu::ActuatorMap m;
  std::stringstream words(channels_());
  std::vector<std::string> names;
  for (std::string w; words >> w;) names.push_back(w);
  if (names.size() != 4)
    throw ParamError("parameter '" + qname("channels") + "': needs 4 names (aileron elevator rudder throttle), got '" + channels_() + "'");
  for (std::size_t i = 0; i < 4; ++i) {
    try {
      m.channel[i] = fcu::channel_index(names[i]);
    } catch (const std::invalid_argument& e) {
      throw ParamError("parameter '" + qname("channels") + "': " + e.what());
    }
    m.sign[i] = signs_()[i];
  }
  m.max_deflection = max_deflection;
  try {
    m.validate();
  } catch (const std::invalid_argument& e) {
    throw ParamError("parameter '" + qname("channels/signs/max_deflection") + "': " + e.what());
  }
  return m;
}

fcu::RcMap FcuSerial::rc_map() const {
  auto index = [this](double v, const char* name) {
    if (v != std::floor(v)) throw ParamError("parameter '" + qname(name) + "': channel " + std::to_string(v) + " is not a whole number");
    return static_cast<int>(v);
  };
  fcu::RcMap m;
  for (std::size_t i = 0; i < 4; ++i) {
    m.stick_channel[i] = index(rc_channels_()[i], "rc_channels");
    m.aux_channel[i] = index(rc_aux_channels_()[i], "rc_aux_channels");
  }
  for (std::size_t i = 0; i < 3; ++i) m.sign[i] = rc_signs_()[i];
  try {
    m.validate();
  } catch (const std::invalid_argument& e) {
    throw ParamError("parameter '" + qname("rc_channels/rc_aux_channels/rc_signs") + "': " + e.what());
  }
  return m;
}

}  // namespace tern::fcu_serial
