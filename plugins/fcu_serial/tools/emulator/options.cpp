// emulator/options.cpp: see options.hpp.
#include "options.hpp"

#include "uart.hpp"

#include <csignal>
#include <iostream>
#include <memory>

#include <sys/prctl.h>

namespace tern::fcu::emulator {

volatile std::sig_atomic_t g_emulator_stop = 0;

void add_world_options(CLI::App& app, Options& o) {
  app.add_option("--aircraft", o.aircraft, "aircraft file (tern or ROSflight format)")->required()->check(CLI::ExistingFile);
  app.add_option("--seed", o.seed, "random seed of turbulence and sensor noise");
  app.add_flag("--udp", o.udp, "UDP instead of a pseudo-terminal (ROSflight SIL ports)");
  app.add_option("--fd", o.fd, "a connected stream socket inherited as this file descriptor, instead of a pseudo-terminal")
      ->check(CLI::Range(3, 1023));
  app.add_option("--udp-host", o.udp_host, "UDP address");
  app.add_option("--udp-port", o.udp_port, "our UDP port (ROSflight SIL: 14525)");
  app.add_option("--udp-remote-port", o.udp_remote_port, "the companion's UDP port (rosflight_io: 14520)");
  app.add_flag("--lockstep", o.lockstep, "wait for one OFFBOARD_CONTROL per IMU sample");
  app.add_option("--baud", o.baud,
                 "pace the pseudo-terminal (or --fd socket) as a UART at this baud rate, 8N1: 10 bit times a byte each way "
                 "(a pty alone moves bytes at memory speed whatever its baud setting); 0: no pacing")
      ->capture_default_str();
  app.add_option("--speed", o.speed, "free-running: simulated seconds per wall second")->check(CLI::Range(0.01, 1000.0));
  app.add_option("--duration", o.duration, "stop after this many simulated seconds (0: run until stopped)");
  app.add_option("--wind", o.wind, "steady wind n,e,d (m/s, NED)");
  app.add_option("--turbulence", o.turbulence, "Dryden turbulence")->check(CLI::IsMember({"none", "light", "moderate"}));
  app.add_option("--init-mode", o.init_mode, "ground (at rest) or air (level)")->check(CLI::IsMember({"ground", "air"}));
  app.add_option("--init-altitude", o.init_altitude, "m (air)");
  app.add_option("--init-airspeed", o.init_airspeed, "m/s (air)");
  app.add_option("--init-heading", o.init_heading, "rad");
  app.add_option("--max-deflection", o.max_deflection, "a,e,r rad at full servo throw (default: the aircraft's limits)");
  app.add_option("--params", o.params, "the FCU's stored parameters, YAML NAME: value (default: the firmware's defaults)");
  app.add_option("--rc", o.rc, "the pilot's transmitter over time, \"T key=value ...; T ...\" or none")->capture_default_str();
  app.add_option("--silence", o.silence, "T0:T1 s: send nothing in this window (link loss)");
  app.add_option("--pitot-cover", o.pitot_cover, "s: the pitot is covered until then (for the FCU's boot calibration in wind)");
  app.add_option("--stall-timeout", o.stall_timeout, "lockstep: run on after this many wall seconds without a command");
  app.add_option("--truth", o.truth, "write the world's true state to this CSV (50 Hz; for benchmarks, never read by the autopilot)");
  app.add_flag("--exit-with-parent", o.exit_with_parent, "stop when the process that started it ends (the plugin passes it)");
}

namespace {
extern "C" void on_signal(int) { g_emulator_stop = 1; }
}  // namespace

int run_on_port(const Options& o, const std::string& program, const std::function<std::function<int()>(Port&)>& make) {
  std::signal(SIGTERM, on_signal);
  std::signal(SIGINT, on_signal);
  std::signal(SIGPIPE, SIG_IGN);
  if (o.exit_with_parent) {
    const pid_t parent = getppid();
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) return 0;  // the parent ended before prctl took effect
  }
  try {
    std::unique_ptr<Port> port;
    std::string where;
    if (o.fd >= 0) {
      port = std::make_unique<FdPort>(o.fd);
      where = "fd: " + std::to_string(o.fd);
    } else if (o.udp) {
      if (o.baud > 0) throw std::runtime_error("--baud " + std::to_string(o.baud) + ": paces a serial line (pty or --fd), not --udp");
      port = std::make_unique<UdpPort>(o.udp_host, o.udp_port, o.udp_remote_port);
      where = "udp: " + o.udp_host + ":" + std::to_string(o.udp_port);
    } else {
      auto pty = std::make_unique<PtyPort>();
      where = std::string("pty: ") + pty->name();
      port = std::move(pty);
    }
    if (o.baud > 0) {
      port = std::make_unique<UartPort>(std::move(port), o.baud);
      std::cerr << program << ": the port paced as a UART at " << o.baud << " baud, 8N1\n";
    }
    const std::function<int()> run = make(*port);
    std::cout << where << std::endl;
    return run();
  } catch (const std::exception& e) {
    std::cerr << program << ": " << e.what() << "\n";
    return 1;
  }
}

}  // namespace tern::fcu::emulator
