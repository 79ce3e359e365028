// `plugin: external` (core/host/runners/external_plugin.hpp) without DDS: its config errors, the error of a
// tern built without DDS, and the lockstep contract with a link that stands in for DDS.
#include <doctest/doctest.h>

#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "runners/external_link.hpp"
#include "test_util.hpp"
#include "tern/msg/control.hpp"
#include "tern/msg/state.hpp"

using namespace tern;
using namespace tern::core;

namespace {

// Records what the host publishes; answers each tick with an actuator command stamped for it,
// except at the ticks in `silent`.
struct FakeModule {
  std::vector<Nanos> published, taken;
  std::vector<Nanos> silent;
  int timeouts = 0;
  int latest_left = 1 << 30;  // --realtime: how many take_latest calls find a new output
  int latest_delay = 0;       // --realtime: how many take_latest calls find nothing before the first output
};

class FakeLink final : public ExternalLink {
 public:
  explicit FakeLink(std::shared_ptr<FakeModule> m) : m_(std::move(m)) {}
  std::vector<std::string> wait_matched(std::chrono::milliseconds) override { return {}; }
  void publish(std::size_t i, const void* tern_msg, Nanos stamp) override {
    CHECK(i == 0);
    CHECK(static_cast<const msg::State*>(tern_msg)->stamp <= stamp);
    m_->published.push_back(stamp);
  }
  bool take(std::size_t, Nanos stamp, void* tern_msg, std::chrono::microseconds) override {
    for (Nanos s : m_->silent)
      if (s == stamp) return ++m_->timeouts, false;
    auto* a = static_cast<msg::Actuators*>(tern_msg);
    *a = msg::Actuators{};
    a->stamp = stamp;
    a->delta_t = 0.25;
    m_->taken.push_back(stamp);
    return true;
  }
  bool take_latest(std::size_t o, Nanos stamp, void* tern_msg) override {
    if (m_->latest_delay > 0) return --m_->latest_delay, false;
    if (m_->latest_left <= 0) return false;
    --m_->latest_left;
    return take(o, stamp, tern_msg, {});
  }

 private:
  std::shared_ptr<FakeModule> m_;
};

const std::string kExternal =
    "  - name: ext\n    plugin: external\n    rate: 50\n"
    "    inputs: [{port: state, topic: estimated_state, type: rosplane_msgs/msg/State}]\n"
    "    outputs: [{port: ext_actuators, topic: command, type: rosflight_msgs/msg/Command}]\n";

}  // namespace

TEST_CASE("external: a tern built without DDS refuses it in one line") {
  set_external_link_factory({});
  const std::string e = build_error(base_config("  - {name: ext, plugin: external, rate: 100, role: controller}\n"));
  CHECK(e.find("plugins[3].plugin: 'external' needs tern built with DDS") != std::string::npos);
}

TEST_CASE("external: config errors name the field and value") {
  set_external_link_factory([](const ExternalSpec&, const MissionConfig&) { return std::unique_ptr<ExternalLink>(); });
  std::string e = build_error(base_config("  - {name: ext, plugin: external, rate: 100, role: controler}\n"));
  CHECK(e.find("plugins[3].role: unknown role 'controler' (roles: controller) (did you mean 'controller'?)") != std::string::npos);
  e =
      build_error(base_config("  - {name: ext, plugin: external, rate: 100, inputs: [{port: state, topic: estimated_state, "
                              "type: rosplane_msgs/msg/Stat}], outputs: [{port: a, topic: command, type: rosflight_msgs/msg/Command}]}\n"));
  CHECK(e.find("plugins[3].inputs[0].type: 'rosplane_msgs/msg/Stat' cannot be an external module's input (it may be: "
               "rosplane_msgs/msg/State, rosplane_msgs/msg/ControllerCommands) (did you mean 'rosplane_msgs/msg/State'?)") !=
        std::string::npos);
  e = build_error(
      base_config("  - {name: ext, plugin: external, rate: 100, inputs: [{port: actuators, topic: command, "
                  "type: rosflight_msgs/msg/Command}], outputs: [{port: a, topic: command, type: rosflight_msgs/msg/Command}]}\n"));
  CHECK(e.find("plugins[3].inputs[0].type: 'rosflight_msgs/msg/Command' cannot be an external module's input") != std::string::npos);
  e = build_error(base_config("  - {name: ext, plugin: external, rate: 100, role: controller, timeout_ms: -3}\n"));
  CHECK(e.find("plugins[3].timeout_ms: expected a number of ms > 0, got '-3'") != std::string::npos);
  e = build_error(base_config("  - {name: ext, plugin: external, rate: 100}\n"));
  CHECK(e.find("an external module needs role: controller, or inputs: and outputs:") != std::string::npos);
  e = build_error(base_config("  - {name: x, plugin: test_controller, rate: 100, role: controller}\n"));
  CHECK(e.find("plugins[3]: unknown key 'role'") != std::string::npos);
  // a tern port of another type than the binding's: the port graph's type check
  e =
      build_error(base_config("  - name: ext\n    plugin: external\n    rate: 50\n"
                              "    inputs: [{port: imu, topic: estimated_state, type: rosplane_msgs/msg/State}]\n"
                              "    outputs: [{port: ext_actuators, topic: command, type: rosflight_msgs/msg/Command}]\n"));
  CHECK(e.find("input 'ext.imu' expects tern/State") != std::string::npos);
  CHECK(e.find("topic 'imu' carries tern/Imu") != std::string::npos);
  set_external_link_factory({});
}

TEST_CASE("external: lockstep: inputs stamped with the tick, outputs taken for the same tick; a miss publishes nothing") {
  auto m = std::make_shared<FakeModule>();
  m->silent = {from_seconds(1.0)};
  set_external_link_factory([m](const ExternalSpec& spec, const MissionConfig&) -> std::unique_ptr<ExternalLink> {
    CHECK(spec.dds_name(spec.inputs[0]) == "rt/estimated_state");
    return std::make_unique<FakeLink>(m);
  });
  const FlightResult r = fly_yaml(base_config(kExternal), "external_lockstep", std::nullopt, 2.0);
  set_external_link_factory({});
  CHECK(r.ok);
  REQUIRE(m->published.size() >= 99);
  CHECK(m->taken.size() + 1 == m->published.size());
  CHECK(m->timeouts == 1);
  for (std::size_t k = 1; k < m->published.size(); ++k) CHECK(m->published[k] - m->published[k - 1] == 20'000'000);  // 50 Hz
  const std::string act = read_file(r.run_dir / "topics" / "ext_actuators.csv");
  CHECK(lines(act).size() == m->taken.size() + 1);  // a header, a row per answered tick
}

namespace {

// Flies kExternal for 1 s in real time (timeout_ms 200, 50 Hz) with the fake module `m`.
FlightResult fly_realtime(const std::shared_ptr<FakeModule>& m, const std::string& name, bool* lockstep = nullptr) {
  set_external_link_factory([=](const ExternalSpec& spec, const MissionConfig&) -> std::unique_ptr<ExternalLink> {
    if (lockstep) *lockstep = spec.lockstep;
    return std::make_unique<FakeLink>(m);
  });
  HostOptions o;
  o.quiet = true;
  o.duration = 1.0;
  o.realtime = true;
  o.log_dir = test_dir() / name;
  std::string cfg = base_config(kExternal);
  cfg.replace(cfg.find("    rate: 50\n"), 13, "    rate: 50\n    timeout_ms: 200\n");
  Host h(load_config(write_file("flight.yaml", cfg)), o);
  h.build();
  const FlightResult r = h.fly();
  set_external_link_factory({});
  return r;
}

double ext_timeouts(const FlightResult& r) {
  return nlohmann::json::parse(read_file(r.run_dir / "summary.json"))["instances"]["ext"]["timeouts"].get<double>();
}

}  // namespace

TEST_CASE("external: --realtime: no lockstep; the newest output is held up to timeout_ms, then the module is silent") {
  auto m = std::make_shared<FakeModule>();
  m->latest_left = 10;  // the module answers 10 times, then stops
  bool lockstep = true;
  // timeout 200 ms at 50 Hz: after the 10th answer, about 10 more steps publish the held output
  const FlightResult r = fly_realtime(m, "external_realtime", &lockstep);
  CHECK(r.ok);
  CHECK_FALSE(lockstep);
  CHECK(m->taken.size() == 10);
  const std::size_t rows = lines(read_file(r.run_dir / "topics" / "ext_actuators.csv")).size() - 1;
  CHECK(rows >= 15);  // 10 taken + the held ones (about 10 steps in 200 ms of wall time)
  CHECK(rows <= 25);
  CHECK(rows < m->published.size());  // then silent: nothing published for the rest of the second
}

// A bug fixed: the steps before the module's first output counted as timeouts (none can exist
// before it has seen an input).
TEST_CASE("external: --realtime: the steps before the first output are no timeouts; a module that never answers times out") {
  auto healthy = std::make_shared<FakeModule>();
  healthy->latest_delay = 3;  // its first answer comes at the 4th step
  const FlightResult r = fly_realtime(healthy, "external_realtime_first");
  CHECK(r.ok);
  CHECK(healthy->taken.size() + 3 == healthy->published.size());
  CHECK(ext_timeouts(r) == 0);
  auto dead = std::make_shared<FakeModule>();
  dead->latest_left = 0;
  const FlightResult d = fly_realtime(dead, "external_realtime_dead");
  CHECK(d.ok);
  // silent once 200 ms have passed since the first input: most of the second's 50 steps, not the first
  CHECK(ext_timeouts(d) > 0);
  CHECK(ext_timeouts(d) < static_cast<double>(dead->published.size()));
}
