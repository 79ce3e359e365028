// emulator/emulator.hpp: tern-fcu-emulator's loop: sim_aero's aircraft, wind and sensors
// behind the emulated ROSflight firmware (tern_fcu_serial/firmware.hpp, fcu_side.hpp).
//
// One loop per IMU period (400 Hz), as ROSflight::run (src/rosflight.cpp) runs on each IMU
// sample: the sensors (SMALL_IMU, then ATTITUDE_QUATERNION at the same rate and
// ROSFLIGHT_OUTPUT_RAW every 8th sample: comm_manager.cpp CommManager::stream; mag 50 Hz,
// baro and pitot 100 Hz, GNSS 10 Hz as the board delivers them), the receiver (RC_CHANNELS and
// the firmware's RC handling on each 50 Hz frame), HEARTBEAT 1 Hz and ROSFLIGHT_STATUS 10 Hz
// (CommManager::send_1hz_heartbeat), then the mixer's outputs move the aircraft's surfaces.
// The aircraft's servos: output 0 aileron, 1 elevator, 2 rudder (PWM fraction 0..1 = -max..+max
// deflection in the uavbook's signs), output 4 the motor (throttle 0..1).
#pragma once

#include <csignal>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "port.hpp"
#include "rc_script.hpp"
#include "truth_log.hpp"
#include "tern_fcu_serial/codec.hpp"
#include "tern_fcu_serial/fcu_side.hpp"
#include "tern/aircraft.hpp"
#include "tern_sim_aero/sensors.hpp"
#include "tern_sim_aero/simulator.hpp"

namespace tern::fcu::emulator {

/// Set by the signal handler of main(): the loop ends.
extern volatile std::sig_atomic_t g_emulator_stop;

struct Options {
  std::string aircraft;
  std::uint64_t seed = 1;
  bool udp = false;
  int fd = -1;  ///< --fd N: an inherited, connected stream socket (fcu_serial's emulator_link: socket)
  std::string udp_host = "127.0.0.1";
  unsigned udp_port = 14525, udp_remote_port = 14520;
  bool lockstep = false;
  double speed = 1.0;
  unsigned baud = 0;  ///< --baud N: the port paced as a UART at N baud, 8N1 (uart.hpp); 0: at memory speed
  double duration = 0;
  std::string wind = "0,0,0";
  std::string turbulence = "none";
  std::string init_mode = "ground";
  double init_altitude = 100, init_airspeed = 17, init_heading = 0;
  std::string max_deflection;                   ///< empty: the aircraft's limits
  std::string params;                           ///< the FCU's stored parameters (YAML NAME: value); empty: defaults
  std::string rc = firmware::kDefaultRcScript;  ///< --rc script (rc_script.hpp)
  std::string silence;
  double reboot_at = -1;
  double corrupt = 0;
  /// The pitot is covered (no dynamic pressure reaches the sensor) until this time, s: what a
  /// pilot does at power-up in wind, so that the boot calibration zeroes the sensor, not the wind.
  double pitot_cover = 0;
  double stall_timeout = 10;
  std::string truth;  ///< --truth FILE: the world's true state (truth_log.hpp); empty: none
  bool exit_with_parent = false;
};

/// The stored parameters of a YAML file (NAME: value), over the firmware's defaults; throws
/// std::runtime_error naming the file, parameter and value at fault.
firmware::Params load_params(const std::string& file);

class Emulator {
 public:
  Emulator(const Options& o, Port& port);
  int run();

 private:
  std::int64_t fcu_time() const { return t_ - boot_ + 1'000'000'000; }  ///< streams from 1 s after power-up
  bool silent(std::int64_t t) const { return silence_ && t >= silence_->first && t < silence_->second; }
  void reboot();
  void service(std::int64_t timeout_ns);
  bool flush();
  /// Appends one frame the firmware sends as itself; returns where it starts in out_.
  template <class T>
  std::size_t send(const T& m) {
    const std::size_t at = out_.size();
    fcu_->send(m, out_);
    return at;
  }
  /// --corrupt: every frame about to be written (streams, answers, echoes alike) has one byte
  /// flipped with that probability; a damaged IMU sample is not delivered.
  void corrupt_frames();
  void step_sensors(std::int64_t t);
  void step_imu(const sim::Truth& truth, std::int64_t t);
  void step_rc(std::int64_t t);
  void step_streams(std::int64_t t);
  void apply_outputs();
  const sim::Truth& truth();

  Options o_;
  Port& port_;
  tern::Aircraft ac_;
  sim::Simulator sim_;
  sim::Sensors sensors_;
  firmware::Params boot_params_;
  std::optional<FcuSide> fcu_;
  RcScript rc_script_;
  std::array<double, 3> throw_{};  ///< servo throw: rad at PWM fraction 1 of aileron, elevator, rudder
  mavlink::Parser parser_;
  std::optional<TruthLog> truth_log_;
  std::mt19937_64 rng_;
  std::vector<std::uint8_t> out_;
  std::optional<sim::Truth> truth_;
  sim::SensorSchedule imu_, mag_, baro_, diff_, gnss_, rc_, status_, heartbeat_;
  std::optional<std::pair<std::int64_t, std::int64_t>> silence_;
  std::int64_t t_ = 0, dt_ = 2'500'000, boot_ = 0;
  std::uint64_t imu_count_ = 0, dropped_ = 0;
  std::optional<std::size_t> imu_at_;  ///< where this loop's SMALL_IMU starts in out_
  bool rebooted_ = false, imu_delivered_ = false;
};

}  // namespace tern::fcu::emulator
