// core/host/runners/external_plugin.hpp: an `external` instance (external_spec.hpp): a module whose code runs
// in another process and whose ports are DDS topics. The host sees a plugin with one input port
// per spec input and one output port per spec output (tern types from the bindings); each step
// runs one lockstep exchange over DDS (ExternalLink):
//   1. publishes every input that has a message, header stamp = the tick's sim time `now`;
//   2. waits, up to timeout_ms for each, for the outputs stamped `now` and publishes them on
//      their tern topics (stamp `now`).
// The module's own computation thus falls inside the tick, as an in-process plugin's does, and a
// flight is as deterministic as the module (the stand-in controller's flights are bit-identical).
// A module that does not answer in time is silent for that tick: nothing is published, so the
// safety monitor (safety_monitor.hpp) sees a silent controller and the phase router hands over
// to the fallback as for a silent plugin (after phase_machine.safety_silent_periods silent steps:
// a dead module costs that many timeouts of wall time, then the fallback flies and the module is
// no longer stepped). The misses are counted in summary.json (`<name>.timeouts`) and the first is
// logged.
// With --realtime (spec.lockstep false) there is no lockstep: the tick is paced to wall time, the
// module runs on /clock (published by the DDS bridge: fly with --dds), and each step publishes
// the inputs, then the newest output that came (any stamp), held while younger than timeout_ms
// of wall time; an older one makes the step silent, as above. Before the module's first output
// a step publishes nothing and counts no timeout until timeout_ms of wall time have passed since
// the first input went out (a module needs an input to answer; one that never answers is silent
// from then on).
// start() waits up to 10 s for the DDS endpoints to match (discovery); unmatched ones are logged.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "runners/external_link.hpp"
#include "config/external_spec.hpp"
#include "tern/plugin.hpp"

namespace tern::core {

class ExternalPlugin final : public Plugin {
 public:
  /// `link` is null when describing (tern check, tern params): ports only.
  ExternalPlugin(ExternalSpec spec, std::unique_ptr<ExternalLink> link);
  ~ExternalPlugin() override;

  void configure() override;
  void start() override;
  void step(Nanos now) override;
  void reset() override {}
  void take_over(const msg::Actuators&) override {}  // the module keeps its own state
  std::vector<std::pair<std::string, double>> summary() const override;

  const ExternalSpec& spec() const { return spec_; }

 private:
  void exchange_outputs(Nanos now);
  bool take_latest_outputs(Nanos now);

  ExternalSpec spec_;
  std::unique_ptr<ExternalLink> link_;
  std::vector<std::unique_ptr<InputBase>> in_;
  std::vector<std::unique_ptr<OutputBase>> out_;
  std::vector<std::vector<unsigned char>> buf_;                                    // per output: the tern message taken
  bool silent_ = false;                                                            // the last exchange missed an output
  std::vector<std::optional<std::chrono::steady_clock::time_point>> last_output_;  // --realtime: when each came
  std::optional<std::chrono::steady_clock::time_point> first_sent_;                // when the first input went out
  std::uint64_t exchanges_ = 0, timeouts_ = 0;
  double wait_us_total_ = 0, wait_us_max_ = 0;  // wall time spent waiting for the module
};

}  // namespace tern::core
