// core/host/graph/realtime.hpp: a paced (--realtime) flight on a companion computer: the flight
// thread's scheduling (SCHED_FIFO priority, CPU affinity, locked memory) and what its clock
// measured (issue 41).
//
// Per tick of a paced flight (scheduler.hpp: tick k ends at wall0 + (k + 1) * period):
//   work         wall time from the tick's start (the previous tick's wake-up) to the end of its
//                steps, ns;
//   deadline     a tick whose work ends after its end time is a deadline miss (it overran its
//                period; the next tick starts late, with no sleep);
//   wake-up      otherwise the thread sleeps until the end time (clock_nanosleep, absolute, on
//                CLOCK_MONOTONIC, the steady clock's) and the wake-up latency is how late it woke;
//   page faults  the flight thread's minor and major faults over the flight (getrusage
//                RUSAGE_THREAD): a major fault is a disk read in the loop, which mlockall prevents.
// Wall-clock figures: in summary.json's "realtime" (paced flights only: an unpaced flight's
// summary stays a pure function of config and seed) and the console's summary.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "graph/scheduler.hpp"

namespace tern::core {

/// How the flight thread runs (`tern fly|serve --realtime --rt-priority N --cpu K --mlockall`).
struct RealtimeOptions {
  int priority = 0;          ///< SCHED_FIFO priority, 1..99; 0: the default scheduler (SCHED_OTHER)
  int cpu = -1;              ///< the one CPU the flight thread runs on; -1: any
  bool lock_memory = false;  ///< mlockall(MCL_CURRENT | MCL_FUTURE): no page of the process is paged out
  /// Flight time per wall time, (0, 1000]: 1 real time, 10 ten times faster (PX4's
  /// PX4_SIM_SPEED_FACTOR); ticks are paced to `speed` times wall time.
  double speed = 1.0;
  /// Any of the thread's settings (not the speed) is asked for.
  bool any() const { return priority != 0 || cpu >= 0 || lock_memory; }
};

/// Applies `o` to the calling thread (priority, affinity) and the process (locked memory).
/// Returns "" or one line naming the option, the call, the system's reason and what to do (e.g.
/// "--rt-priority 80: pthread_setschedparam(SCHED_FIFO) not permitted (Operation not permitted):
/// run as root, or grant rtprio in /etc/security/limits.conf or CAP_SYS_NICE").
std::string apply_realtime(const RealtimeOptions& o);

/// "SCHED_FIFO 80, CPU 1, memory locked", or "SCHED_OTHER, any CPU, memory not locked".
std::string describe(const RealtimeOptions& o);

/// What the clock of a paced flight measured (see the file comment).
class RealtimeStats {
 public:
  /// The first tick starts at wall `now` (ns, wall_ns()); takes the thread's fault counts.
  void begin(std::int64_t now);
  /// The tick's steps ended at wall `now`; the tick ends at `deadline`. True when it missed it.
  bool work_done(std::int64_t now, std::int64_t deadline);
  /// The pacing sleep for `deadline` ended at wall `now`: the next tick starts.
  void woke(std::int64_t now, std::int64_t deadline);
  /// Takes the thread's fault counts again (call on the flight thread when it ends).
  void end();

  std::uint64_t ticks() const { return work_.steps; }
  std::uint64_t misses() const { return misses_; }
  const StepStats& wake_up() const { return wake_; }
  const StepStats& work() const { return work_; }
  long minor_faults() const { return minor_; }
  long major_faults() const { return major_; }

  /// summary.json's "realtime": settings, ticks, misses (count and share), wake-up latency and
  /// work per tick (p50, p99, max, us), page faults.
  nlohmann::ordered_json to_json(const RealtimeOptions& o) const;
  /// The console line: "real time: SCHED_OTHER, ...; 240000 ticks, 0 deadline misses; wake-up
  /// p50 62 us, p99 110 us, max 290 us; work p50 ...; page faults 12 minor, 0 major".
  std::string line(const RealtimeOptions& o) const;

 private:
  StepStats wake_, work_;
  std::uint64_t misses_ = 0;
  std::int64_t tick_start_ = 0;
  long minor0_ = 0, major0_ = 0, minor_ = 0, major_ = 0;
};

}  // namespace tern::core
