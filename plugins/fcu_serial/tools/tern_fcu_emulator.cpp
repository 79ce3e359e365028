// tern-fcu-emulator: plays a ROSflight flight-control unit over a pseudo-terminal (or UDP),
// with sim_aero's aircraft model, wind and sensor models behind the emulated firmware
// (tern_fcu_serial/firmware.hpp: arming, errors, RC, command muxing, mixer, calibration, as
// rosflight_firmware does them), so that tern flies through the real serial path.
//
//   tern-fcu-emulator --aircraft configs/aircraft/anaconda.yaml [--lockstep] [--params FCU.yaml]
//                     [--rc "0 throttle=0 aux1=-1; 2 aux1=1"]
//
// prints "pty: /dev/pts/N" (or "udp: HOST:PORT") on stdout, then streams (emulator/emulator.hpp).
// Pacing: free-running at --speed times real time (1: like a real FCU), or --lockstep: after
// each IMU sample that reached the companion it waits for one OFFBOARD_CONTROL before it
// integrates the next IMU period. Faults for tests: --silence T0:T1 (sends nothing),
// --reboot-at T (boots again), --corrupt P (each frame has one byte flipped with probability
// P), --pitot-cover T (the pitot covered until T, for the boot calibration in wind); the pilot:
// --rc (emulator/rc_script.hpp).
#include <functional>
#include <memory>

#include <CLI/CLI.hpp>

#include "emulator/emulator.hpp"
#include "emulator/options.hpp"

using namespace tern::fcu::emulator;

int main(int argc, char** argv) {
  CLI::App app{"tern-fcu-emulator: a ROSflight FCU on a pseudo-terminal (or UDP), flying sim_aero's aircraft"};
  Options o;
  add_world_options(app, o);
  app.add_option("--reboot-at", o.reboot_at, "s: the FCU reboots (its clock restarts at 0)");
  app.add_option("--corrupt", o.corrupt, "probability that a frame gets one byte flipped")->check(CLI::Range(0.0, 1.0));
  CLI11_PARSE(app, argc, argv);

  return run_on_port(o, "tern-fcu-emulator", [&](Port& port) {
    auto emu = std::make_shared<Emulator>(o, port);
    return std::function<int()>([emu] { return emu->run(); });
  });
}
