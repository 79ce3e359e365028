// tern/testing/harness.hpp: run one plugin alone, without the host, from a doctest test.
//
//   tern::testing::Harness h(std::make_unique<MyController>(), {{"kp", 0.5}});
//   h.set_input("state", state_msg);        // feeds the input port named "state"
//   h.step(tern::from_seconds(0.01));        // one step at t = 10 ms
//   auto& a = h.output<tern::msg::Actuators>("actuators");
//
// The harness is a tern::Context: parameters come from the map given to the constructor
// (validated as the host would), the seed is fixed, logs go to a console logger. Link
// tern::sdk_testing. Errors (unknown port, wrong message type) throw std::logic_error.
#pragma once

#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "tern/plugin.hpp"

namespace tern::testing {

struct HarnessOptions {
  std::string instance = "test";
  std::uint64_t seed = 1;
  std::filesystem::path config_dir;     ///< relative path parameters resolve against this
  std::filesystem::path aircraft_file;  ///< what Context::aircraft_file() returns
  YAML::Node mission;                   ///< what Context::mission() returns
  std::vector<std::string> vehicles;    ///< what Context::vehicles() returns (a coordination plugin's)
};

class TERN_API Harness final : public Context {
 public:
  using Options = HarnessOptions;

  /// Attaches and configures the plugin (throws what configure() throws).
  explicit Harness(std::unique_ptr<Plugin> plugin, std::map<std::string, ParamValue> params = {}, Options options = {});
  ~Harness() override;

  Plugin& plugin() { return *plugin_; }

  /// Publishes msg to the plugin's input port `port` (created and bound on first use). Several
  /// before one step reach an input with a queue (Input<T>::received()) each, in order.
  template <class T>
  void set_input(const std::string& port, const T& msg) {
    InputBase* in = plugin_->find_input(port);
    if (in == nullptr) throw std::logic_error("harness: plugin has no input port '" + port + "'");
    check_type(*in, msg_type_v<T>);
    auto it = feeders_.find(port);
    if (it == feeders_.end()) {
      auto out = std::make_unique<Output<T>>();
      out->keep_history(in->queue_depth());  // as the host sizes a producer for its queued readers
      in->bind(out.get());
      it = feeders_.emplace(port, std::move(out)).first;
    }
    static_cast<Output<T>&>(*it->second).publish(msg);
  }

  /// Runs start() (once, automatically before the first step if not called).
  void start();
  /// One step at flight time `now`; marks the inputs seen afterwards, as the host does.
  void step(Nanos now);
  /// Between flights, as the host: the plugin's reset(), then its outputs and the inputs fed
  /// by set_input() emptied (no message until the next set_input()).
  void reset();
  void stop();

  /// Latest message on output port `port` (throws if unknown or of another type).
  template <class T>
  const T& output(const std::string& port) const {
    const OutputBase* out = plugin_->find_output(port);
    if (out == nullptr) throw std::logic_error("harness: plugin has no output port '" + port + "'");
    check_type(*out, msg_type_v<T>);
    return static_cast<const Output<T>*>(out)->last();
  }
  /// How many messages output `port` has published.
  std::uint64_t published(const std::string& port) const;

  /// Sets a parameter as the command line or DDS would (validated; throws ParamError).
  void set_param(const std::string& name, const ParamValue& value);

  // Context
  const std::string& instance_name() const override { return options_.instance; }
  std::optional<ParamValue> configured_value(const std::string& param, const ParamSpec& spec) const override;
  std::uint64_t seed() const override { return options_.seed; }
  std::shared_ptr<spdlog::logger> logger() const override { return logger_; }
  std::filesystem::path config_dir() const override { return options_.config_dir; }
  const YAML::Node& mission() const override { return options_.mission; }
  std::filesystem::path aircraft_file() const override { return options_.aircraft_file; }
  std::vector<std::string> vehicles() const override { return options_.vehicles; }
  /// Records the first request (reason, detail); the harness steps on regardless.
  void end_flight(const std::string& reason, const std::string& detail) override {
    if (!end_request_) end_request_.emplace(reason, detail);
  }
  /// What the plugin's first end_flight() asked (reason, detail), if it did.
  const std::optional<std::pair<std::string, std::string>>& end_request() const { return end_request_; }

 private:
  static void check_type(const PortBase& port, const MsgType& want);
  std::map<std::string, ParamValue> params_;
  Options options_;
  std::shared_ptr<spdlog::logger> logger_;
  std::map<std::string, std::unique_ptr<OutputBase>> feeders_;
  std::unique_ptr<Plugin> plugin_;  // destroyed before the feeders it reads
  bool started_ = false;
  std::optional<std::pair<std::string, std::string>> end_request_;
};

}  // namespace tern::testing
