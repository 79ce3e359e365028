// PortGraph alone: topics, type checks, order and binding from ports built here, no plugin loaded.
#include <doctest/doctest.h>

#include <memory>
#include <string>
#include <vector>

#include "config/error.hpp"
#include "graph/port_graph.hpp"
#include "tern/msg/all.hpp"

using namespace tern;
using namespace tern::core;

namespace {

// The ports of one node, owned here (a plugin would own them).
struct Ports {
  std::vector<std::unique_ptr<OutputBase>> outs;
  std::vector<std::unique_ptr<InputBase>> ins;
  template <class T>
  Output<T>& out(const std::string& name) {
    auto p = std::make_unique<Output<T>>();
    p->set_identity(name, "");
    auto& ref = *p;
    outs.push_back(std::move(p));
    return ref;
  }
  template <class T>
  Input<T>& in(const std::string& name, Need need = Need::required) {
    auto p = std::make_unique<Input<T>>();
    p->set_identity(name, "");
    p->set_need(need);
    auto& ref = *p;
    ins.push_back(std::move(p));
    return ref;
  }
  PortNode node(const std::string& name, bool io = false, bool routed = false) const {
    PortNode n{name, io, routed, {}, {}};
    for (const auto& o : outs) n.outputs.push_back(o.get());
    for (const auto& i : ins) n.inputs.push_back(i.get());
    return n;
  }
};

const std::filesystem::path kFile = "/missions/m.yaml";

std::string graph_error(const std::vector<PortNode>& nodes, const std::vector<const OutputBase*>& host = {}) {
  try {
    PortGraph g(nodes, host, kFile);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("port graph: I/O first, then producers before consumers; a consumer scheduled first reads over a feedback edge") {
  Ports ctl, filter, sensor;
  ctl.in<msg::State>("state");
  ctl.out<msg::Actuators>("actuators");
  filter.in<msg::Imu>("imu");
  filter.out<msg::State>("state");
  sensor.in<msg::Actuators>("actuators");
  sensor.out<msg::Imu>("imu");
  const PortGraph g({ctl.node("ctl"), filter.node("filter"), sensor.node("sensor", true)}, {}, kFile);
  CHECK(g.order() == std::vector<std::size_t>{2, 1, 0});
  REQUIRE(g.edges().size() == 3);
  CHECK(g.feedback(2, "actuators"));  // the sensor runs before the controller: previous tick
  CHECK_FALSE(g.feedback(1, "imu"));
  CHECK_FALSE(g.feedback(0, "state"));
  // topics in order of first appearance, node by node, outputs first
  REQUIRE(g.topics().size() == 3);
  CHECK(g.topics()[0].name == "actuators");
  CHECK(g.topics()[1].name == "state");
  CHECK(g.topics()[2].name == "imu");
  CHECK(g.topics()[2].type_name == "tern/Imu");
  CHECK(g.topics()[2].msg_size == sizeof(msg::Imu));
}

TEST_CASE("port graph: in a cycle without I/O the earliest node goes first") {
  Ports a, b;
  a.in<msg::State>("y");
  a.out<msg::State>("x");
  b.in<msg::State>("x");
  b.out<msg::State>("y");
  const PortGraph g({a.node("a"), b.node("b")}, {}, kFile);
  CHECK(g.order() == std::vector<std::size_t>{0, 1});
  CHECK(g.feedback(0, "y"));
  CHECK_FALSE(g.feedback(1, "x"));
}

TEST_CASE("port graph: binding follows the topic; remaps change the topic, not the port") {
  Ports w, r;
  auto& out = w.out<msg::State>("estimate");
  out.set_topic("state");
  auto& in = r.in<msg::State>("state");
  PortGraph g({w.node("w"), r.node("r")}, {}, kFile);
  CHECK_FALSE(in.connected());  // building binds nothing
  g.bind(std::nullopt);
  CHECK(in.source() == &out);
  CHECK(g.find("state")->current == &out);
  CHECK(g.port_id(0, out) == "w.estimate");
  CHECK_FALSE(in.updated());
  msg::State s;
  s.p_d = -12.5;
  out.publish(s);
  CHECK(in.updated());
  CHECK(in->p_d == -12.5);
}

TEST_CASE("port graph: one writer per topic, except controllers behind the phase router") {
  Ports c1, c2, sim;
  auto& a1 = c1.out<msg::Actuators>("actuators");
  auto& a2 = c2.out<msg::Actuators>("actuators");
  auto& in = sim.in<msg::Actuators>("actuators");
  CHECK(graph_error({c1.node("c1"), c2.node("c2"), sim.node("sim", true)}) ==
        "/missions/m.yaml: topic 'actuators' has 2 writers: c1.actuators, c2.actuators (only controllers behind the phase router, "
        "named in 'phases:', may share a topic; remap one of them)");
  CHECK(graph_error({c1.node("c1", false, true), c2.node("c2"), sim.node("sim", true)}).find("has 2 writers") != std::string::npos);
  PortGraph g({c1.node("c1", false, true), c2.node("c2", false, true), sim.node("sim", true)}, {}, kFile);
  CHECK(g.find("actuators")->routed);
  g.bind(1);  // the active controller's output, only
  CHECK(in.source() == &a2);
  g.route(0);
  CHECK(in.source() == &a1);
  CHECK(g.find("actuators")->current == &a1);
  g.route(std::nullopt);  // no controller runs: the reader has no writer
  CHECK_FALSE(in.connected());
  CHECK(g.find("actuators")->current == nullptr);
}

TEST_CASE("port graph: route_topic takes over a topic a plugin writes downstream of a remapped controller; route() gives it back") {
  // control_slc's actuators remapped to controller_actuators, a signal generator adding the
  // excitation and publishing actuators: the host's termination and state-loss recovery still
  // reach the aircraft.
  Ports ctl, gen, sim, host;
  auto& c = ctl.out<msg::Actuators>("actuators");
  c.set_topic("controller_actuators");
  gen.in<msg::Actuators>("controller_actuators");
  auto& g_out = gen.out<msg::Actuators>("actuators");
  auto& in = sim.in<msg::Actuators>("actuators");
  auto& host_cmd = host.out<msg::Actuators>("actuators");
  PortGraph g({ctl.node("ctl", false, true), gen.node("gen"), sim.node("sim", true)}, {}, kFile);
  CHECK_FALSE(g.find("actuators")->routed);
  g.bind(0);
  CHECK(in.source() == &g_out);
  CHECK(g.route_topic("actuators", &host_cmd));
  CHECK(in.source() == &host_cmd);
  CHECK(g.find("actuators")->current == &host_cmd);  // what the log records
  g.route(0);
  CHECK(in.source() == &g_out);
  CHECK(g.find("actuators")->current == &g_out);
  CHECK_FALSE(g.route_topic("no_such_topic", &host_cmd));
}

TEST_CASE("port graph: writers and readers of a topic must carry one message type") {
  Ports c1, c2, r;
  c1.out<msg::Actuators>("actuators");
  c2.out<msg::State>("actuators");
  CHECK(graph_error({c1.node("c1", false, true), c2.node("c2", false, true)})
            .find("/missions/m.yaml: topic 'actuators': writers disagree on the message type: c1.actuators publishes tern/Actuators (") ==
        0);
  Ports w;
  w.out<msg::State>("state");
  r.in<msg::Imu>("state");
  const std::string e = graph_error({w.node("w"), r.node("r")});
  CHECK(e.find("/missions/m.yaml: input 'r.state' expects tern/Imu (") == 0);
  CHECK(e.find("but topic 'state' carries tern/State (") != std::string::npos);
  CHECK(e.find("from 'w.state'") != std::string::npos);
}

TEST_CASE("port graph: a required input needs a writer; an optional one stays unconnected") {
  Ports sensor, filter;
  sensor.out<msg::Imu>("imu");
  filter.in<msg::Imu>("imu2");
  CHECK(graph_error({sensor.node("sensor", true), filter.node("filter")}) ==
        "/missions/m.yaml: input 'filter.imu2' (topic 'imu2', tern/Imu) has no producer: no instance publishes 'imu2' (did you mean "
        "'imu'?); add a plugin that does or remap the input");
  Ports opt;
  auto& mag = opt.in<msg::Mag>("mag", Need::optional);
  PortGraph g({sensor.node("sensor", true), opt.node("ekf")}, {}, kFile);
  g.bind(std::nullopt);
  CHECK_FALSE(mag.connected());
  CHECK(g.describe_topics().find("  mag [tern/Mag]: (none) -> ekf.mag (optional, unconnected)\n") != std::string::npos);
}

TEST_CASE("port graph: the host's own output feeds a topic that is read and not written") {
  Output<msg::MissionEdit> edits;
  edits.set_identity("mission_edit", "");
  Ports planner, other;
  auto& in = planner.in<msg::MissionEdit>("mission_edit", Need::optional);
  PortGraph g({planner.node("planner")}, {&edits}, kFile);
  CHECK(g.offers(&edits));
  g.bind(std::nullopt);
  CHECK(in.source() == &edits);
  CHECK(g.describe_topics() == "  mission_edit [tern/MissionEdit]: host -> planner.mission_edit\n");
  // nobody reads it: not offered
  const PortGraph unread({other.node("other")}, {&edits}, kFile);
  CHECK_FALSE(unread.offers(&edits));
  // a plugin writes it: the plugin's output wins
  Ports writer;
  writer.out<msg::MissionEdit>("mission_edit");
  const PortGraph written({writer.node("gcs"), planner.node("planner")}, {&edits}, kFile);
  CHECK_FALSE(written.offers(&edits));
  // a reader of another type is refused
  Ports wrong;
  wrong.in<msg::State>("mission_edit", Need::optional);
  CHECK(graph_error({wrong.node("w")}, {&edits}) ==
        "/missions/m.yaml: input 'w.mission_edit' on topic 'mission_edit' expects tern/State, the host publishes tern/MissionEdit");
}
