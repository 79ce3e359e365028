// PhaseRouter alone: two in-test controllers and a reader of `actuators` in a port graph, the
// phase machine through the SDK's test harness. Routing follows the phase table (a phase it
// does not name is flown by cruise's controller, preflight by none), the routed topic is bound
// to the active controller only, the incoming controller takes over from the last good command,
// and a failing controller is replaced by the fallback in the same tick, for the rest of the
// flight; a failing fallback ends the flight.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <spdlog/sinks/null_sink.h>
#include <spdlog/spdlog.h>

#include "graph/instances.hpp"
#include "graph/port_graph.hpp"
#include "safety/phase_machine.hpp"
#include "safety/phase_router.hpp"
#include "tern/testing/harness.hpp"

using namespace tern;
using namespace tern::core;
using tern::testing::Harness;

namespace {

/// A controller that commands `command` each step (or throws), and remembers its handovers.
class TestController final : public Plugin {
 public:
  void configure() override { declare(out_, "actuators", "surface and throttle command"); }
  void step(Nanos now) override {
    ++steps;
    if (throws) throw std::runtime_error("boom");
    msg::Actuators a = command;
    a.stamp = now;
    out_.publish(a);
  }
  void take_over(const msg::Actuators& last) override {
    ++take_overs;
    taken_over_from = last;
  }

  msg::Actuators command{0, 0.1, 0.05, 0.0, 0.6};
  bool throws = false;
  int steps = 0, take_overs = 0;
  msg::Actuators taken_over_from{};

 private:
  Output<msg::Actuators> out_;
};

/// Instances "slc" and "tecs" (controllers), "spare" (a controller no table names), the reader
/// of `actuators` (an estimator's input, here a bare port), the phase machine and the router.
struct Rig {
  /// `topic`: where the controllers' actuators go (a remap, e.g. to a signal generator's input).
  explicit Rig(std::map<msg::Phase, std::string> phases, std::optional<std::string> fallback = std::nullopt, bool preflight = false,
               const std::string& topic = "actuators")
      : pm(std::make_unique<PhaseMachine>(), {{"preflight", preflight},
                                              {"preflight_time", 0.0},
                                              {"alt_toz", 5.0},
                                              {"alt_hz", 20.0},
                                              {"min_phase_time", 0.0},
                                              {"safety", false}}) {
    for (const char* name : {"slc", "tecs", "spare"}) {
      auto inst = std::make_unique<Instance>();
      inst->cfg.name = name;
      inst->info.kind = PluginKind::controller;
      inst->plugin = std::make_unique<TestController>();
      inst->plugin->configure();
      for (auto* o : inst->plugin->outputs()) o->set_topic(topic);
      instances.push_back(std::move(inst));
    }
    reader.set_identity(topic, "");
    config.phases = std::move(phases);
    config.fallback = std::move(fallback);
    router = std::make_unique<PhaseRouter>(instances, graph, log);
    router->assign(config, &machine());
    std::vector<PortNode> nodes;
    for (const auto& inst : instances)
      if (!inst->idle) nodes.push_back({inst->cfg.name, false, inst->routed, inst->plugin->outputs(), {}});
    nodes.push_back({"estimator", false, false, {}, {&reader}});
    graph = PortGraph(nodes, {}, "/missions/m.yaml");
    graph.bind(router->active());
    router->prepare_flight();
    pm.start();
    router->start_flight();
  }

  PhaseMachine& machine() { return static_cast<PhaseMachine&>(pm.plugin()); }
  TestController& ctl(std::size_t i) { return static_cast<TestController&>(*instances[i]->plugin); }

  /// One tick at t seconds at altitude `alt`: the phase machine, the router following it, the
  /// active controller and the router's verdict on its step. Returns that verdict.
  std::string tick(double t, double alt) {
    const Nanos now = from_seconds(t);
    msg::State s;
    s.p_d = -alt;
    s.valid = true;
    s.status = msg::StateStatus::ok;
    pm.set_input("state", s);
    pm.step(now);
    router->follow_phase(now);
    const auto active = router->active();
    if (!active) return "";
    return router->after_controller_step(now, *active, step(*instances[*active], now), [&](Instance& i) { return step(i, now); });
  }
  static std::string step(Instance& i, Nanos now) {
    try {
      i.plugin->step(now);
      return "";
    } catch (const std::exception& e) {
      return e.what();
    }
  }

  Harness pm;
  std::shared_ptr<spdlog::logger> log = std::make_shared<spdlog::logger>("router", std::make_shared<spdlog::sinks::null_sink_mt>());
  std::vector<std::unique_ptr<Instance>> instances;
  Input<msg::Actuators> reader;
  MissionConfig config;
  PortGraph graph;
  std::unique_ptr<PhaseRouter> router;
};

constexpr std::size_t kSlc = 0, kTecs = 1, kSpare = 2;

}  // namespace

TEST_CASE("phase router: the table picks the controller, the unnamed phase flies cruise's, only the active one is read") {
  Rig r({{msg::Phase::takeoff, "slc"}, {msg::Phase::cruise, "tecs"}});
  CHECK(r.instances[kSlc]->routed);
  CHECK(r.instances[kTecs]->routed);
  CHECK(r.instances[kSpare]->idle);  // a controller the table does not name never steps
  CHECK_FALSE(r.router->may_step(kSpare));
  REQUIRE(r.router->fallback() == kTecs);  // no fallback: cruise's controller
  REQUIRE(r.router->active() == kSlc);
  CHECK(r.router->may_step(kSlc));
  CHECK_FALSE(r.router->may_step(kTecs));

  r.ctl(kSlc).command.delta_e = 0.11;
  r.ctl(kTecs).command.delta_e = 0.22;
  CHECK(r.tick(0.1, 1.0).empty());
  CHECK(r.reader.get().delta_e == 0.11);
  CHECK(r.ctl(kTecs).steps == 0);

  CHECK(r.tick(0.2, 6.0).empty());  // climb: not in the table, so cruise's controller flies
  CHECK(r.machine().phase() == msg::Phase::climb);
  REQUIRE(r.router->active() == kTecs);
  CHECK(r.reader.get().delta_e == 0.22);
  CHECK(r.ctl(kTecs).take_overs == 1);
  CHECK(r.ctl(kTecs).taken_over_from.delta_e == 0.11);  // bumpless: slc's last good command
  REQUIRE(r.router->handovers().size() == 1);
  CHECK(r.router->handovers()[0].from == "slc");
  CHECK(r.router->handovers()[0].to == "tecs");
  CHECK(r.router->handovers()[0].reason == "phase climb");
  CHECK(r.router->handovers()[0].t == from_seconds(0.2));
  CHECK_FALSE(r.router->fallback_engaged());
}

TEST_CASE("phase router: preflight runs no controller; the takeoff routes to takeoff's") {
  Rig r({{msg::Phase::takeoff, "slc"}, {msg::Phase::cruise, "tecs"}}, std::nullopt, true);
  CHECK_FALSE(r.router->active());
  REQUIRE(r.graph.find("actuators") != nullptr);
  CHECK(r.graph.find("actuators")->current == nullptr);  // bound to slc before start_flight, unbound by it
  REQUIRE(r.router->handovers().size() == 1);
  CHECK(r.router->handovers()[0].to == "(none)");

  r.tick(0.1, 0.0);  // the checks pass (preflight_time 0): takeoff
  CHECK(r.machine().phase() == msg::Phase::takeoff);
  CHECK(r.router->active() == kSlc);
  CHECK(r.ctl(kSlc).steps == 1);
  CHECK(r.graph.find("actuators")->current == r.instances[kSlc]->plugin->outputs().front());
  CHECK(r.reader.has_value());
}

TEST_CASE("phase router: a controller that fails is replaced by the fallback in the same tick, for the rest of the flight") {
  struct Failure {
    const char* name;
    void (*make)(TestController&);
    const char* reason;
  };
  const Failure failures[] = {
      {"throws", [](TestController& c) { c.throws = true; }, "slc.step threw: boom"},
      {"non-finite", [](TestController& c) { c.command.delta_e = std::numeric_limits<double>::quiet_NaN(); }, "non-finite"},
      {"beyond max_deflection", [](TestController& c) { c.command.delta_a = 0.8; }, "outside the actuator limits"},
      {"throttle above 1", [](TestController& c) { c.command.delta_t = 1.2; }, "outside the actuator limits"},
      {"non-finite brake", [](TestController& c) { c.command.brake = std::numeric_limits<double>::quiet_NaN(); }, "non-finite"},
      {"brake above 1", [](TestController& c) { c.command.brake = 1.5; }, "outside the actuator limits"},
  };
  for (const Failure& f : failures) {
    CAPTURE(f.name);
    Rig r({{msg::Phase::takeoff, "slc"}, {msg::Phase::climb, "slc"}, {msg::Phase::cruise, "slc"}}, "tecs");
    r.ctl(kSlc).command.delta_e = 0.07;
    r.ctl(kTecs).command.delta_e = 0.3;
    REQUIRE(r.tick(0.1, 1.0).empty());
    f.make(r.ctl(kSlc));
    CHECK(r.tick(0.2, 1.0).empty());  // handled: the flight goes on
    CHECK(r.router->fallback_engaged());
    REQUIRE(r.router->active() == kTecs);
    CHECK(r.ctl(kTecs).steps == 1);  // stepped in the failing tick
    CHECK(r.reader.get().delta_e == 0.3);
    CHECK(r.ctl(kTecs).taken_over_from.delta_e == 0.07);  // the last good command, not the failing one
    REQUIRE(r.router->handovers().size() == 1);
    CHECK(r.router->handovers()[0].reason.find(f.reason) != std::string::npos);
    CHECK(r.router->handovers()[0].reason.find("fallback for the rest of the flight") == 0);

    r.tick(0.3, 6.0);  // a new phase whose controller is slc: the fallback keeps flying
    CHECK(r.machine().phase() == msg::Phase::climb);
    CHECK(r.router->active() == kTecs);
    CHECK(r.router->handovers().size() == 1);
  }
}

TEST_CASE("phase router: a controller whose actuators are remapped (to a signal generator) is watched all the same") {
  Rig r({{msg::Phase::takeoff, "slc"}, {msg::Phase::climb, "slc"}, {msg::Phase::cruise, "slc"}}, "tecs", false, "controller_actuators");
  r.ctl(kSlc).command.delta_e = 0.07;
  r.ctl(kTecs).command.delta_e = 0.3;
  REQUIRE(r.tick(0.1, 1.0).empty());
  CHECK(r.reader.get().delta_e == 0.07);
  r.ctl(kSlc).command.delta_e = std::numeric_limits<double>::quiet_NaN();
  CHECK(r.tick(0.2, 1.0).empty());
  CHECK(r.router->fallback_engaged());
  CHECK(r.reader.get().delta_e == 0.3);
  CHECK(r.ctl(kTecs).taken_over_from.delta_e == 0.07);
}

TEST_CASE("phase router: when the fallback itself fails, the flight ends with an error") {
  Rig r({{msg::Phase::takeoff, "tecs"}, {msg::Phase::cruise, "tecs"}}, "tecs");
  REQUIRE(r.router->active() == kTecs);
  r.ctl(kTecs).throws = true;
  const std::string verdict = r.tick(0.1, 1.0);
  CHECK(verdict.rfind("error: tecs.step threw: boom", 0) == 0);
  CHECK(verdict.find("no fallback controller left") != std::string::npos);
}

TEST_CASE("phase router: a fallback that fails in the tick it takes over ends the flight") {
  Rig r({{msg::Phase::takeoff, "slc"}, {msg::Phase::cruise, "slc"}}, "tecs");
  r.ctl(kSlc).throws = true;
  r.ctl(kTecs).throws = true;
  CHECK(r.tick(0.1, 1.0) == "error: fallback tecs.step threw: boom");
}

TEST_CASE("phase router: a table naming a non-controller is refused with the field and the controllers there are") {
  Rig r({{msg::Phase::takeoff, "slc"}, {msg::Phase::cruise, "tecs"}});
  r.instances[kSpare]->info.kind = PluginKind::estimator;
  r.instances[kSpare]->info.name = "estimator_ekf";
  MissionConfig bad = r.config;
  bad.phases[msg::Phase::cruise] = "spare";
  bad.phases_option = "--phases cruise=spare";
  std::string what;
  try {
    r.router->assign(bad, &r.machine());
  } catch (const std::exception& e) {
    what = e.what();
  }
  CHECK(what ==
        "--phases cruise=spare: phases.cruise: 'spare' is not a controller: it runs plugin 'estimator_ekf' (estimator); name one of: slc, "
        "tecs");
}
