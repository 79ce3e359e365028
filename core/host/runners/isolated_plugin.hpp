// core/host/runners/isolated_plugin.hpp: an instance that runs in a child process (`isolate: true` in the
// mission config), so that a crash, a hang or an exit of its plugin cannot take the host down.
//
// The host keeps a "shadow" of the plugin, configured in-process as usual (it declares the
// ports and parameters the port graph binds and `tern serve` edits) but never started or
// stepped. IsolatedPlugin presents the shadow's ports and parameters as its own and runs every
// call of the plugin's life in the child, `tern-isolate` (isolate_main.cpp), in lockstep over
// shared memory (isolation_channel.hpp):
//   before a call   the inputs' latest messages (copied only when new), their bound/updated
//                   state, and the parameters changed since the last call (Param::on_change)
//   after it        the outputs (publish_copy with the child's sequence numbers), the log
//                   lines (to the instance's logger: console and tern.log), an end_flight()
//                   request, the error text of a throw (rethrown here as std::runtime_error)
// The child steps the same plugin code on the same bytes, so a flight is bit-identical with and
// without isolation.
//
// Why fork+exec of a helper rather than fork after load: the host is multithreaded (the log
// writer, DDS, spdlog), and a fork copies only the forking thread, with whatever locks the others
// held: the child could deadlock in malloc or in a logger. A fresh process loads the config and
// the library itself and starts clean; between fork and exec only async-signal-safe calls run.
// The child ignores SIGINT/SIGTERM/SIGHUP (the host ends the flight and then the child), and
// dies with the host (PR_SET_PDEATHSIG).
//
// Failure: when the child dies from a signal, exits, or a call runs longer than `hard_budget`
// (wall time; the child is then killed with SIGKILL), the instance is failed for the rest of the
// flight: the call throws IsolatedFailure and failure() says "isolated instance X died:
// SIGSEGV" (or "exited with status 3", "hung: no reply within 2 s, killed with SIGKILL"). The
// host then engages the fallback (a routed controller) or ends the flight (anything else). The
// next flight's reset() or start() starts a new child. Errors while starting the child (no
// `tern-isolate`, a port whose message is not plain bytes, configure failing in the child) are
// ConfigError.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "runners/isolation_channel.hpp"
#include "tern/plugin.hpp"

namespace tern::core {

namespace fs = std::filesystem;

/// What the child needs to build the same instance.
struct IsolationSpec {
  fs::path config_file;      ///< the mission config the child loads
  std::string instance;      ///< instance name in it
  fs::path library;          ///< the .so the child opens (a hot-swap's private copy)
  std::uint64_t seed;        ///< the flight's seed (the child derives the instance's as the host does)
  Nanos hard_budget;         ///< wall time a call may take before the child is killed, ns
  std::string fleet_part{};  ///< the config's part in a multi-vehicle mission (MissionConfig::fleet_part), "" if none
};

/// A call to an isolated instance whose child died, exited or hung.
class IsolatedFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class IsolatedPlugin final : public Plugin {
 public:
  /// Takes the configured shadow (attached to `ctx`, which outlives this) and starts the child.
  /// Throws ConfigError.
  IsolatedPlugin(std::unique_ptr<Plugin> shadow, Context& ctx, IsolationSpec spec);
  ~IsolatedPlugin() override;  ///< asks the child to quit (SIGKILL after 1 s), then drops the shadow

  void configure() override {}
  void start() override;
  void step(Nanos now) override;
  void reset() override;
  void take_over(const msg::Actuators& last_command) override;
  void stop() override;
  std::vector<std::pair<std::string, double>> summary() const override { return summary_; }

  /// Why the instance failed this flight ("" while it works).
  const std::string& failure() const { return failure_; }
  pid_t child() const { return pid_; }

 private:
  void map_segment();
  void spawn();
  void end_child();
  /// Runs `c` in the child: inputs and parameters in, outputs, log and end request out.
  void call(isolation::Command c);
  bool wait_done(Nanos budget);
  void copy_inputs();
  void copy_outputs();
  void deliver_reply();
  void send_params(bool all);
  char* base() const { return static_cast<char*>(map_); }

  std::unique_ptr<Plugin> shadow_;
  IsolationSpec spec_;
  int fd_ = -1;
  void* map_ = nullptr;
  std::size_t size_ = 0;
  isolation::Header* h_ = nullptr;
  pid_t pid_ = -1;
  std::vector<const OutputBase*> copied_src_;  // per input: the writer whose message the slot holds
  std::vector<std::uint64_t> copied_seq_;      //   and its sequence number
  std::vector<std::uint64_t> seq_base_;        // per output: shadow sequence = child's + base
  std::vector<char> dirty_;                    // per parameter: changed since the last call
  std::string failure_;
  std::vector<std::pair<std::string, double>> summary_;
};

}  // namespace tern::core
