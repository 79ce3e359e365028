// tern-fcu-sil: the REAL ROSflight firmware (compiled from the tree given to CMake as
// TERN_ROSFLIGHT_FIRMWARE_DIR) on tern's software-in-the-loop board, with sim_aero's aircraft,
// wind and raw sensors behind it, speaking MAVLink over a pseudo-terminal (or UDP) as the
// flight-control unit does over its UART (sil/sil.hpp).
//
//   tern-fcu-sil --aircraft configs/aircraft/anaconda.yaml [--lockstep] [--params FCU.yaml]
//                [--rc "0 throttle=0 aux1=-1; 9 aux1=1"] [--flash FILE] [--outputs 0,1,2,4]
//
// prints "pty: /dev/pts/N" (or "udp: HOST:PORT") on stdout, then runs. The options of the world
// (aircraft, wind, start, pacing, pilot, link silence) are tern-fcu-emulator's.
#include <functional>
#include <memory>

#include <CLI/CLI.hpp>

#include "emulator/options.hpp"
#include "sil/sil.hpp"

using namespace tern::fcu;

int main(int argc, char** argv) {
  CLI::App app{std::string("tern-fcu-sil: the ROSflight firmware (") + sil::firmware_version() +
               ") on a pseudo-terminal (or UDP), flying sim_aero's aircraft"};
  sil::SilOptions o;
  emulator::add_world_options(app, o.world);
  app.add_option("--flash", o.flash, "the board's parameter flash file (kept between runs); default: a fresh one per run");
  app.add_option("--outputs", o.outputs, "firmware outputs (0-based) driving aileron, elevator, rudder, motor")->capture_default_str();
  app.add_option("--sensor-profile", o.sensor_profile, "sim_aero sensor and actuator profile of the raw sensors")
      ->check(CLI::IsMember({"realistic", "rosflight", "ideal"}))
      ->capture_default_str();
  app.add_option("--companion-silence", o.companion_silence,
                 "T0:T1 s: the companion's bytes do not reach the firmware in this window (its OFFBOARD_TIMEOUT hands the "
                 "aircraft to the pilot)");
  app.add_flag("--bench-calibration", o.bench_calibration,
               "before the flight, calibrate the IMU on the bench (level, still) with the firmware's own calibration and "
               "save it to flash, as ROSflight asks before flying");
  CLI11_PARSE(app, argc, argv);
  return emulator::run_on_port(o.world, "tern-fcu-sil", [&](emulator::Port& port) {
    auto sil = std::make_shared<sil::Sil>(o, port);
    return std::function<int()>([sil] { return sil->run(); });
  });
}
