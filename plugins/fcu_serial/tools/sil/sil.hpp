// sil/sil.hpp: tern-fcu-sil's loop: sim_aero's aircraft, wind and raw sensors behind the REAL
// ROSflight firmware (its `ROSflight` object and `MavlinkAdapter`, compiled unchanged from the
// tree given to CMake) on tern's board (sil_board.hpp), talking MAVLink over a pseudo-terminal
// (or UDP) exactly as the flight-control unit does over its UART.
//
// One loop per IMU period (400 Hz), t in ns since power-up:
//  1. the world's sensors due at t go to the board (IMU every period; mag 50 Hz, baro and pitot
//     100 Hz, GNSS 10 Hz delivered gnss_latency after its time of validity; the pilot's receiver
//     50 Hz), raw: the `realistic` profile's errors without any calibration (the firmware's own
//     calibrations remove them: gyro and accelerometer on command or at arming, baro and pitot
//     at boot: sensors.cpp);
//  2. ROSflight::run() (src/rosflight.cpp): sensors, estimator, controller, mixer, pwm_write,
//     streams, receive, state machine, RC, command muxing;
//  3. what it wrote to its serial port goes out; --lockstep: the loop waits for one
//     OFFBOARD_CONTROL from the companion per IMU sample that reached it; otherwise it keeps
//     --speed times real time, running the firmware again whenever the companion's bytes
//     arrive during the wait (a board's main loop spins: TIMESYNC is answered on arrival);
//  4. ROSflight::run() once more with no new sensor data: on a board the main loop spins between
//     IMU samples, so a command that arrived is received and muxed before the next sample
//     (it reaches the mixer with that sample: one IMU period after it was sent);
//  5. the outputs (pwm_write) move the aircraft's servos and motor at each output's PWM pulse
//     (pwm_init's rate: 50 Hz for the fixed-wing mixers' outputs), through --outputs (which
//     output drives aileron, elevator, rudder, motor) and the servo throw;
//  6. sim_aero integrates one IMU period.
// Time: the board clock reads 1 s at the first loop (as the emulator's: the boot takes time).
// A reboot (ROSFLIGHT_CMD_REBOOT) constructs and boots the firmware again from its flash; its
// clock keeps counting, since the firmware keeps per-process state in function-local statics
// (comm_manager.cpp send_1hz_heartbeat, stream) that only a real power cycle would reset.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "../emulator/emulator.hpp"
#include "sil_board.hpp"

namespace rosflight_firmware {
class ROSflight;
class MavlinkAdapter;
}  // namespace rosflight_firmware

namespace tern::fcu::sil {

struct SilOptions {
  emulator::Options world;          ///< aircraft, seed, port, pacing, wind, start, pilot, faults
  std::string flash;                ///< parameter flash file; empty: a fresh one per run (deleted at exit)
  std::string outputs = "0,1,2,4";  ///< firmware outputs driving aileron, elevator, rudder, motor (fixedwing_mixing)
  std::string sensor_profile = "realistic";
  /// T0:T1 s: the companion's bytes do not reach the firmware (a cut wire, a hung companion);
  /// lockstep still counts its commands, so the world keeps stepping.
  std::string companion_silence;
  /// Before the flight, the firmware calibrates the IMU on the bench and saves it (sil_bench.cpp).
  bool bench_calibration = false;
};

/// The firmware's version string: what its CMake puts in GIT_VERSION_STRING.
const char* firmware_version();

class Sil {
 public:
  Sil(const SilOptions& o, emulator::Port& port);
  ~Sil();
  int run();

 private:
  std::int64_t board_us(std::int64_t t) const { return (t + 1'000'000'000) / 1000; }
  void boot();
  void upload_params();
  void bench_calibration();
  int run_bench();
  sim::Truth bench_truth() const;
  void put_sensors(std::int64_t t);
  void put_imu(std::int64_t t);
  void put_gnss(std::int64_t t);
  void put_rc(std::int64_t t);
  void run_firmware();
  bool flush();
  bool service(std::int64_t timeout_ns);
  void wait_free_running(std::int64_t wall0);
  void wait_for_command(std::uint64_t& used);
  void apply_outputs(std::int64_t t);
  const sim::Truth& truth();

  SilOptions o_;
  emulator::Port& port_;
  tern::Aircraft ac_;
  sim::Simulator sim_;
  sim::Sensors sensors_;
  emulator::RcScript rc_script_;
  SilBoard board_;
  std::unique_ptr<rosflight_firmware::MavlinkAdapter> adapter_;
  std::unique_ptr<rosflight_firmware::ROSflight> fw_;
  std::optional<emulator::TruthLog> truth_log_;
  mavlink::Parser monitor_;  ///< counts the companion's OFFBOARD_CONTROL frames (lockstep)
  std::uint64_t commands_ = 0;
  std::array<int, 4> outputs_{};   ///< output index of aileron, elevator, rudder, motor
  std::array<double, 3> throw_{};  ///< rad at PWM fraction 1 of aileron, elevator, rudder
  std::array<float, 4> held_{};    ///< what the servos and motor hold between pulses
  std::array<std::int64_t, 4> next_pulse_{};
  std::vector<std::uint8_t> out_;
  std::optional<sim::Truth> truth_;
  std::deque<std::pair<std::int64_t, rosflight_firmware::GnssStruct>> gnss_pending_;  ///< delivery time, fix
  sim::SensorSchedule imu_, mag_, baro_, diff_, gnss_, rc_;
  std::optional<std::pair<std::int64_t, std::int64_t>> silence_, deaf_;
  std::int64_t t_ = 0, dt_ = 2'500'000, gnss_latency_ = 0;
  std::uint64_t dropped_ = 0, reboots_ = 0;
  bool imu_sent_ = false;
  bool temporary_flash_ = false;
};

}  // namespace tern::fcu::sil
