// Issue 22 item 1: --set, --phases, --fallback on the command line (cli_overrides.hpp), checked
// like the same value in the file, one line naming the option and value; controllers the phase
// table does not name are idle (no "topic 'actuators' has 2 writers").
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include "config/cli_overrides.hpp"
#include "test_process.hpp"
#include "test_util.hpp"

using namespace tern::core;

namespace {

const std::string kTwoControllers =
    base_config("  - {name: ctl2, plugin: test_controller, rate: 100, params: {tag: 0.2}}\n",
                "phases: {takeoff: ctl, climb: ctl, cruise: ctl2}\nphase_machine: {alt_toz: 2, alt_hz: 3, preflight: false}\n");

/// The one-line error of loading `yaml`, applying `o` and building ("" if none).
std::string override_error(const CliOverrides& o, const std::string& yaml = kTwoControllers) {
  try {
    MissionConfig mc = load_config(write_file("ovr.yaml", yaml));
    apply_overrides(mc, o);
    HostOptions ho;
    ho.describing = true;
    ho.quiet = true;
    Host h(std::move(mc), ho);
    h.build();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

/// The run directory `tern fly -q` printed ("log: DIR").
fs::path run_dir_of(const std::string& out) {
  for (const auto& l : lines(out))
    if (l.rfind("log: ", 0) == 0) return l.substr(5);
  return {};
}

/// The values of column `name` (its header starts with it) of a topic CSV.
std::vector<std::string> column(const fs::path& csv, const std::string& name) {
  const auto rows = lines(read_file(csv));
  std::vector<std::string> out;
  if (rows.empty()) return out;
  const auto head = cells(rows[0]);
  std::size_t k = 0;
  while (k < head.size() && head[k] != name && head[k].rfind(name + " ", 0) != 0) ++k;
  for (std::size_t i = 1; i < rows.size() && k < head.size(); ++i) out.push_back(cells(rows[i])[k]);
  return out;
}

CliOverrides sets(std::vector<std::string> s) {
  CliOverrides o;
  o.sets = std::move(s);
  return o;
}

CliOverrides phases(std::vector<std::string> p, std::optional<std::string> fallback = {}) {
  CliOverrides o;
  o.phases = std::move(p);
  o.fallback = std::move(fallback);
  return o;
}

}  // namespace

TEST_CASE("--set: a good value reaches the plugin, a bad one is refused as in the file, naming the option") {
  MissionConfig mc = load_config(write_file("ovr.yaml", kTwoControllers));
  apply_overrides(mc, sets({"ctl.kp=0.25", "ctl2.tag=-0.5", "phase_machine.alt_hz=4"}));
  HostOptions ho;
  ho.describing = true;
  ho.quiet = true;
  Host h(std::move(mc), ho);
  h.build();
  for (const auto& [name, p] : h.parameters()) {
    if (name == "ctl.kp") CHECK(std::get<double>(p->value()) == 0.25);
    if (name == "ctl2.tag") CHECK(std::get<double>(p->value()) == -0.5);
    if (name == "phase_machine.alt_hz") CHECK(std::get<double>(p->value()) == 4.0);
  }
  CHECK(override_error(sets({"clt.kp=1"}))
            .rfind("--set clt.kp=1: no plugin instance named 'clt' (did you mean 'ctl'?) (the config's: "
                   "sensor, filter, ctl, ctl2)",
                   0) == 0);
  CHECK(override_error(sets({"ctl.kq=1"})) == "--set ctl.kq=1: unknown parameter 'kq' of plugin 'test_controller' (did you mean 'kp'?)");
  CHECK(override_error(sets({"ctl.kp=fast"})) ==
        "--set ctl.kp=fast: parameter 'ctl.kp': value \"fast\" has the wrong type: expected a number, got a string");
  CHECK(override_error(sets({"ctl.kp=11"})) == "--set ctl.kp=11: parameter 'ctl.kp': value 11 is outside the valid range [0, 10] 1/m");
  CHECK(override_error(sets({"ctl.kp"})) == "--set 'ctl.kp': give INSTANCE.PARAM=VALUE, e.g. --set slc.roll_kp=0.5");
  CHECK(override_error(sets({"kp=1"})) == "--set 'kp=1': give INSTANCE.PARAM=VALUE, e.g. --set slc.roll_kp=0.5");
  CHECK(override_error(sets({"ctl.kp=[1,"})).rfind("--set ctl.kp=[1,: the value is not YAML: ", 0) == 0);
  CHECK(override_error(sets({"ctl.kp="})) == "--set ctl.kp=: expected a value: a number, true/false, text or [a, b, c]");
  CHECK(override_error(sets({"ctl.kp={a: 1}"})) == "--set ctl.kp={a: 1}: expected a value: a number, true/false, text or [a, b, c]");
}

TEST_CASE("--phases replaces the table, --fallback the fallback; unknown phases and instances are named") {
  CHECK(override_error(phases({"takeoff=ctl2,climb=ctl2", "cruise=ctl"}, "ctl2")) == "");
  CHECK(override_error(phases({"takeoff=ctl,climb=ctl,crusie=ctl2"})) ==
        "--phases takeoff=ctl,climb=ctl,crusie=ctl2: unknown phase 'crusie' (did you mean 'cruise'?) (one of takeoff, climb, cruise, "
        "landing, loiter, approach, flare, rollout)");
  CHECK(override_error(phases({"takeoff=ctl,climb=ctl,cruise=ctl3"}))
            .rfind("--phases takeoff=ctl,climb=ctl,cruise=ctl3: cruise: no plugin instance named 'ctl3' (did you mean 'ctl'?)", 0) == 0);
  CHECK(override_error(phases({"takeoff=ctl,climb=ctl"})) ==
        "--phases takeoff=ctl,climb=ctl: no controller for phase 'cruise' (the table is replaced: takeoff, climb and cruise are required)");
  CHECK(override_error(phases({"takeoff=ctl,climb=ctl,takeoff=ctl2,cruise=ctl"})) ==
        "--phases takeoff=ctl,climb=ctl,takeoff=ctl2,cruise=ctl: phase 'takeoff' is given twice");
  CHECK(override_error(phases({"takeoff:ctl"})) ==
        "--phases takeoff:ctl: 'takeoff:ctl' is not PHASE=INSTANCE (e.g. takeoff=slc,climb=slc,cruise=tecs)");
  CHECK(override_error(phases({"takeoff=ctl,climb=ctl,cruise=filter"})) ==
        "--phases takeoff=ctl,climb=ctl,cruise=filter: phases.cruise: 'filter' is not a controller: it runs plugin 'test_filter' "
        "(estimator); name one of: ctl, ctl2");
  CHECK(override_error(phases({}, "sensor")) ==
        "--fallback sensor: fallback: 'sensor' is not a controller: it runs plugin 'test_sensor' (io); name one of: ctl, ctl2");
  CHECK(override_error(phases({}, "ctl9")).rfind("--fallback ctl9: no plugin instance named 'ctl9' (did you mean 'ctl'?)", 0) == 0);
  CHECK(override_error(phases({}, "ctl"), base_config()) == "--fallback ctl: needs a phase table (the config's phases: or --phases)");
  // a table on the command line gives a mission without one its phase machine
  CHECK(override_error(phases({"takeoff=ctl,climb=ctl,cruise=ctl"}), base_config()) == "");
}

TEST_CASE("a controller the phase table does not name is idle: no second writer of actuators, never steps") {
  const std::string yaml = base_config("  - {name: ctl2, plugin: test_controller, rate: 100, params: {tag: 0.2}}\n",
                                       "phases: {takeoff: ctl, climb: ctl, cruise: ctl}\n"
                                       "phase_machine: {alt_toz: 2, alt_hz: 3, preflight: false}\n");
  // without a table both write actuators: still refused
  CHECK(build_error(base_config("  - {name: ctl2, plugin: test_controller, rate: 100}\n")).find("topic 'actuators' has 2 writers") !=
        std::string::npos);
  HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / "idle";
  Host h(load_config(write_file("idle.yaml", yaml)), o);
  h.build();
  const std::string graph = h.graph_text();
  CHECK(graph.find("ctl2 (test_controller, controller) 100 Hz  (not routed: idle, never steps, writes nothing)") != std::string::npos);
  CHECK(graph.find("ctl2.actuators") == std::string::npos);
  const FlightResult r = h.fly();
  REQUIRE(r.ok);
  const auto timing = nlohmann::json::parse(read_file(r.run_dir / "timing.json"));
  CHECK(timing["instances"]["ctl2"]["steps"] == 0);
  CHECK(timing["instances"]["ctl"]["steps"] > 150);  // 100 Hz for 2 s
  const auto delta_e = column(r.run_dir / "topics" / "actuators.csv", "delta_e");
  REQUIRE(delta_e.size() > 150);
  for (const auto& v : delta_e) CHECK(std::stod(v) == 0.0);  // ctl's tag (ctl2's is 0.2): ctl flew throughout
}

TEST_CASE("tern fly --set --phases --fallback: the run's config.yaml holds the values flown and names the options") {
  const fs::path cfg = write_file("cli_ovr.yaml", kTwoControllers);
  const fs::path out = test_dir() / "cli_ovr.out";
  const int rc = run_tern({"fly", cfg.string(), "-q", "--log-dir", (test_dir() / "cli_ovr_runs").string(), "--set", "ctl2.tag=0.3",
                           "--phases", "takeoff=ctl2,climb=ctl2,cruise=ctl2", "--fallback", "ctl"},
                          out);
  REQUIRE(rc == 0);
  const fs::path run = run_dir_of(read_file(out));
  REQUIRE(!run.empty());
  const std::string flown = read_file(run / "config.yaml");
  CHECK(flown.find("# with --phases takeoff=ctl2,climb=ctl2,cruise=ctl2 --fallback ctl --set ctl2.tag=0.3\n") != std::string::npos);
  CHECK(flown.find("phases: {takeoff: ctl2, climb: ctl2, cruise: ctl2}") != std::string::npos);
  CHECK(flown.find("fallback: ctl") != std::string::npos);
  CHECK(flown.find("tag: 0.29999999999999999") != std::string::npos);  // ctl2 flew 0.3 (as the emitter writes it)
  CHECK(read_file(run / "tern.log").find("command line: --phases takeoff=ctl2,climb=ctl2,cruise=ctl2 --fallback ctl --set ctl2.tag=0.3") !=
        std::string::npos);
  const auto params = lines(read_file(run / "params.csv"));
  CHECK(std::find(params.begin(), params.end(), "0.000000000,ctl2.tag,0.3,--set ctl2.tag=0.3") != params.end());
  // tern params shows the value the option sets
  CHECK(run_tern({"params", cfg.string(), "--set", "ctl.kp=0.25"}, out) == 0);
  bool listed = false;
  for (const auto& l : lines(read_file(out))) listed = listed || (l.rfind("ctl.kp ", 0) == 0 && l.find(" 0.25 ") != std::string::npos);
  CHECK(listed);
  // and one error line for a bad value, naming the option
  CHECK(run_tern({"check", cfg.string(), "--set", "ctl.kp=11"}, out) == 1);
  CHECK(read_file(out) == "tern: error: --set ctl.kp=11: parameter 'ctl.kp': value 11 is outside the valid range [0, 10] 1/m\n");
}
