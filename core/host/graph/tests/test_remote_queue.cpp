// RemoteQueue alone: requests from other threads wait for the next tick; parameter changes are
// applied in arrival order and recorded with the tick's time and source; a value refused at
// apply time is not applied and not recorded; start-only changes asked between flights are
// applied before the start (at t = 0), live ones too; mission edits reach
// the planner one per tick, in order; pilot input is a latest-value slot.
#include <doctest/doctest.h>

#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <spdlog/sinks/null_sink.h>
#include <spdlog/spdlog.h>

#include "config/error.hpp"
#include "graph/remote_queue.hpp"

using namespace tern;
using namespace tern::core;

namespace {

struct Change {
  Nanos t;
  std::string name, value, source;
};

struct Rig {
  Rig() {
    gain.init(1.0);
    gain.set_identity("gain", "ctl.gain", ParamSpec("", 0.0, 10.0, "a live gain"), 1.0);
    profile.init("calm");
    profile.set_identity("profile", "sim.profile", ParamSpec("", 0, 0, "a start-only choice").start_only(), std::string("calm"));
  }
  RemoteQueue::ParamRecorder recorder() {
    return [this](Nanos t, const std::string& name, const ParamBase& p, const std::string& source) {
      changes.push_back({t, name, to_string(p.value()), source});
    };
  }
  Param<double> gain;
  Param<std::string> profile;
  std::vector<Change> changes;
  spdlog::logger log{"remote", std::make_shared<spdlog::sinks::null_sink_mt>()};
  RemoteQueue q;
};

}  // namespace

TEST_CASE("remote queue: parameter changes wait for the tick, then apply in arrival order, each recorded with time and source") {
  Rig r;
  std::thread other([&] {
    r.q.request_param(r.gain, "ctl.gain", 2.0, "dds");
    r.q.request_param(r.gain, "ctl.gain", 3.0, "cli");
  });
  other.join();
  CHECK(r.gain() == 1.0);  // nothing changes between ticks
  r.q.apply(from_seconds(4.5), r.recorder(), r.log);
  CHECK(r.gain() == 3.0);
  REQUIRE(r.changes.size() == 2);
  CHECK(r.changes[0].t == from_seconds(4.5));
  CHECK(r.changes[0].name == "ctl.gain");
  CHECK(r.changes[0].value == to_string(ParamValue(2.0)));
  CHECK(r.changes[0].source == "dds");
  CHECK(r.changes[1].value == to_string(ParamValue(3.0)));
  CHECK(r.changes[1].source == "cli");

  r.q.apply(from_seconds(4.6), r.recorder(), r.log);  // applied once
  CHECK(r.changes.size() == 2);
}

TEST_CASE("remote queue: a value the parameter refuses when applied keeps the old one and is not recorded") {
  Rig r;
  r.q.request_param(r.gain, "ctl.gain", 20.0, "dds");  // beyond [0, 10]
  r.q.request_param(r.gain, "ctl.gain", 5.0, "dds");
  r.q.apply(from_seconds(1.0), r.recorder(), r.log);
  CHECK(r.gain() == 5.0);
  REQUIRE(r.changes.size() == 1);
  CHECK(r.changes[0].value == to_string(ParamValue(5.0)));
}

TEST_CASE("remote queue: between flights, every change (start-only and live) applies before the start at t = 0") {
  Rig r;
  r.q.request_param(r.gain, "ctl.gain", 2.0, "cli");
  r.q.request_param(r.profile, "sim.profile", std::string("gusty"), "cli");
  r.q.apply_before_start(r.recorder(), r.log);
  CHECK(r.profile() == "gusty");
  CHECK(r.gain() == 2.0);
  REQUIRE(r.changes.size() == 2);
  CHECK(r.changes[0].t == 0);
  CHECK(r.changes[1].t == 0);

  r.q.apply(from_seconds(0.01), r.recorder(), r.log);
  CHECK(r.changes.size() == 2);  // not applied twice
}

TEST_CASE("remote queue: mission edits reach topic mission_edit one per tick, in arrival order, stamped with the tick") {
  Rig r;
  const auto* out = static_cast<const Output<msg::MissionEdit>*>(r.q.renew_mission_edit_output());
  r.q.keep_mission_edit_output(true);
  REQUIRE(r.q.takes_mission_edits());
  for (std::uint32_t id : {7u, 8u, 9u}) {
    msg::MissionEdit e;
    e.id = id;
    e.op = msg::MissionEdit::clear;
    r.q.edit_mission(e);
  }
  CHECK(out->sequence() == 0);
  for (std::uint32_t k = 0; k < 3; ++k) {
    r.q.apply(from_seconds(1.0 + k), r.recorder(), r.log);
    CHECK(out->sequence() == k + 1);
    CHECK(out->last().id == 7 + k);
    CHECK(out->last().stamp == from_seconds(1.0 + k));
  }
  r.q.apply(from_seconds(5.0), r.recorder(), r.log);
  CHECK(out->sequence() == 3);  // nothing left
}

TEST_CASE("remote queue: at most kMaxQueued edits and parameter changes wait; one more is refused, not held") {
  // fuzz_mission_protocol's finding: between flights nothing drains the queue, and a ground
  // station's MISSION_CLEAR_ALL flood grew the host's memory without bound
  Rig r;
  r.q.renew_mission_edit_output();
  r.q.keep_mission_edit_output(true);
  msg::MissionEdit e;
  e.op = msg::MissionEdit::clear;
  for (std::size_t k = 0; k < RemoteQueue::kMaxQueued; ++k) {
    e.id = static_cast<std::uint32_t>(k + 1);
    r.q.edit_mission(e);
    r.q.request_param(r.gain, "ctl.gain", 2.0, "dds");
  }
  e.id = 1001;
  CHECK_THROWS_WITH_AS(
      r.q.edit_mission(e),
      "mission edit #1001 refused: 1000 mission edits already wait for the next ticks (a flood of requests between flights?)", ConfigError);
  CHECK_THROWS_WITH_AS(
      r.q.request_param(r.gain, "ctl.gain", 3.0, "dds"),
      "ctl.gain: not changed: 1000 parameter changes already wait for the next tick (a flood of requests between flights?)", ConfigError);
  CHECK_NOTHROW(r.q.edit_mission(e, /*own=*/true));  // a failsafe's edit is never refused
  CHECK(r.q.queued_edits() == RemoteQueue::kMaxQueued + 1);
  r.q.apply(from_seconds(1.0), r.recorder(), r.log);  // every change and one edit
  r.q.apply(from_seconds(1.01), r.recorder(), r.log);
  CHECK(r.q.queued_edits() == RemoteQueue::kMaxQueued - 1);
  CHECK(r.changes.size() == RemoteQueue::kMaxQueued);
  CHECK_NOTHROW(r.q.edit_mission(e));
  CHECK_NOTHROW(r.q.request_param(r.gain, "ctl.gain", 3.0, "dds"));
}

TEST_CASE("remote queue: a graph that does not take the mission-edit output drops it") {
  Rig r;
  r.q.renew_mission_edit_output();
  r.q.keep_mission_edit_output(false);
  CHECK_FALSE(r.q.takes_mission_edits());
}

TEST_CASE("remote queue: pilot input is the newest set before the tick, published once") {
  Rig r;
  const auto* out = static_cast<const Output<msg::Rc>*>(r.q.renew_pilot_output());
  r.q.keep_pilot_output(true);
  REQUIRE(r.q.takes_pilot());
  msg::Rc rc;
  rc.roll = 0.2;
  r.q.set_pilot(rc);
  rc.roll = -0.5;
  r.q.set_pilot(rc);
  r.q.apply(from_seconds(2.0), r.recorder(), r.log);
  CHECK(out->sequence() == 1);
  CHECK(out->last().roll == -0.5);
  CHECK(out->last().stamp == from_seconds(2.0));
  r.q.apply(from_seconds(2.1), r.recorder(), r.log);
  CHECK(out->sequence() == 1);  // no new input: nothing published
}
