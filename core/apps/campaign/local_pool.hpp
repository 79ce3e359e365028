// core/apps/campaign/local_pool.hpp: runs commands as child processes, `workers` at a time.
//
// Why processes (not in-process hosts on threads): a flight is exactly the `tern fly` command
// its row records, so re-flying it alone is the same code path; a plugin that aborts or leaks
// ends one flight, not the campaign; the host's stop signal is process-wide. The cost, a
// process start and plugin loading per flight (tens of ms), is small beside a flight.
//
// Each child writes its stdout and stderr to its job's console file, runs in its own process
// group (a terminal's Ctrl-C reaches only the campaign) and gets SIGTERM if the campaign dies
// (PR_SET_PDEATHSIG). On SIGINT/SIGTERM/SIGHUP the pool starts no more jobs, sends SIGTERM to
// the running ones (they end their flights and close their logs), waits, and returns false.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace tern::campaign {

struct Job {
  std::size_t index = 0;
  std::vector<std::string> argv;
  std::filesystem::path console;  ///< stdout and stderr of the child
};

/// Runs `jobs` in order on at most `workers` (>= 1) children; `on_done(index, wait status)` is
/// called as each ends (on this thread). Returns false when interrupted by a signal.
bool run_local(const std::vector<Job>& jobs, int workers, const std::function<void(std::size_t, int)>& on_done);

/// Installs the SIGINT/SIGTERM/SIGHUP handlers that interrupt run_local (and wait_child).
void install_interrupt_handlers();
/// The signal that interrupted the campaign, 0 if none.
int interrupted();

}  // namespace tern::campaign
