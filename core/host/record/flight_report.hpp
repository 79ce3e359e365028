// core/host/record/flight_report.hpp: what a flight did, as the flight log's documents and the console
// summary.
//
//   config.yaml    the config as flown: resolved_config.hpp
//   summary.json   mission, seed, end reason, phases and controller handovers, per instance
//                  its library (path, FNV-1a of its bytes), steps and summary() figures, the
//                  metrics (RMSE tables, waypoint passages); same config + seed: same bytes,
//                  whichever flight of a served host it is
//   timing.json    the host's flight number, wall and CPU time, real-time factor, per-instance
//                  step-time statistics
//   summary text   the console's end-of-flight table (stdout, unless quiet)
// Pure functions of the host's state after a flight; nothing here changes it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "config/config.hpp"
#include "graph/instances.hpp"
#include "safety/failsafe.hpp"
#include "safety/phase_router.hpp"

namespace tern::core {

class PhaseMachine;
class FlightMetrics;

struct FlightResult {
  fs::path run_dir;
  std::string end_reason;  ///< "duration", "aborted" (Host::abort_flight), "SIGINT", "SIGTERM", "SIGHUP", "error: ...", or a plugin's
                           ///< end_flight reason ("crash")
  std::string end_detail;  ///< with a plugin's end_flight: "instance at t=...: what it said"; else empty
  /// A flight the watchdog ended: the instance whose step never returned. Its summary() is not
  /// called (its step still runs on the flight thread); summary.json says so instead.
  std::string stuck_instance;
  bool ok = true;
  std::string log_error;  ///< the flight log's first write error: some of the log is missing ("" if none)
  Nanos flown = 0;
  double wall_s = 0;
  double flight_cpu_s = 0;  ///< CPU time of the flight thread (the plugins and the host's loop)
  double log_cpu_s = 0;     ///< CPU time of the flight log's writer thread (CSV formatting, writes)
  std::string summary;      ///< the console's end-of-flight tables (summary_text), for `tern remote fly`
  /// A paced flight's real-time figures (flight/realtime.hpp: summary.json "realtime") and its
  /// console line; null and "" for an unpaced flight.
  nlohmann::ordered_json realtime;
  std::string realtime_line;
};

/// Exit status of `tern fly` and `tern replay` (README, "Exit status"): 1 when !ok, 3 when the
/// log is incomplete, 130/143/129 after SIGINT/SIGTERM/SIGHUP, else 0.
int exit_status(const FlightResult& r);

/// The host's state a report reads (all owned by the host).
struct FlightFacts {
  const MissionConfig& config;
  std::uint64_t seed;
  double duration_s;  ///< the flight length asked for
  int flight;         ///< 1 for a host's first flight
  Nanos base_period;
  const std::vector<std::unique_ptr<Instance>>& instances;
  const PhaseMachine* phase_machine;  ///< nullptr without `phases:`
  const PhaseRouter& router;
  const FlightMetrics* metrics;  ///< nullptr when nothing publishes `state`
  double start_to_first_tick_ms;
  const std::vector<FailsafeEvent>& failsafes;  ///< engagements and cleared causes, in time order
};

std::string summary_json(const FlightFacts& f, const FlightResult& r);
std::string timing_json(const FlightFacts& f, const FlightResult& r);
std::string summary_text(const FlightFacts& f, const FlightResult& r);

}  // namespace tern::core
