// Inputs that parse but mean nothing the host can fly are refused in one line naming file, field
// and value (issue 19, item 5): rates, durations, seeds, names, logged topics, parameters that
// a plugin reads only at start.
#include <doctest/doctest.h>

#include "commands/command_line.hpp"
#include "test_process.hpp"
#include "test_util.hpp"

namespace {

/// base_config() with `from` replaced by `to`.
std::string edited(const std::string& from, const std::string& to, const std::string& extra_top = "") {
  std::string cfg = base_config("", extra_top);
  cfg.replace(cfg.find(from), from.size(), to);
  return cfg;
}

std::string cfg_path() { return (test_dir() / "cfg.yaml").string(); }

/// `tern fly` with a bad option: its exit code and console output.
std::pair<int, std::string> fly_cli(const std::vector<std::string>& extra) {
  std::vector<std::string> args = {"fly", write_file("cli.yaml", base_config()).string(), "-q", "--log-dir",
                                   (test_dir() / "cli_runs").string()};
  args.insert(args.end(), extra.begin(), extra.end());
  const fs::path out = test_dir() / "cli.out";
  const int rc = run_tern(args, out);
  return {rc, read_file(out)};
}

}  // namespace

TEST_CASE("rates the scheduler cannot run") {
  CHECK(build_error(edited("rate: 400", "rate: 1e9")) ==
        cfg_path() + ":6:47: plugins[0].rate: 1e9 Hz is above the scheduler's limit of 10000 Hz");
  CHECK(build_error(edited("rate: 400", "rate: 0")) == cfg_path() + ":6:47: plugins[0].rate: must be > 0 Hz, got 0");
  CHECK(build_error(base_config("", "base_rate: 20000\n")) ==
        cfg_path() + ":5:12: base_rate: 20000 Hz is above the scheduler's limit of 10000 Hz");
  CHECK(build_error(edited("rate: 100}", "rate: 100, budget_us: 0}")) == cfg_path() + ":8:64: plugins[2].budget_us: must be > 0 us, got 0");
  CHECK(build_error(edited("rate: 400", "rate: 10000")).find("100 Hz cannot be served") == std::string::npos);  // the limit itself is fine
}

TEST_CASE("durations: finite, > 0 and at most kMaxDurationS, in the config and on the command line") {
  CHECK(build_error(edited("duration: 2", "duration: 1e10")) ==
        cfg_path() + ":3:11: duration: must be at most 1000000 s (11.6 days), got 10000000000");
  CHECK(build_error(edited("duration: 2", "duration: .nan")) == cfg_path() + ":3:11: duration: expected a number, got '.nan'");
  for (const auto& [value, what] :
       std::vector<std::pair<std::string, std::string>>{{"1e10", "must be at most 1000000 s (11.6 days), got 10000000000"},
                                                        {"nan", "must be a finite number of seconds, got nan"},
                                                        {"inf", "must be a finite number of seconds, got inf"},
                                                        {"0", "must be > 0 s, got 0"},
                                                        {"2s", "'2s' is not a number of seconds"}}) {
    const auto [rc, out] = fly_cli({"--duration", value});
    CHECK(rc != 0);
    CHECK(out == "tern: error: --duration: " + what + " (see --help)\n");
  }
}

TEST_CASE("seeds: an integer 0 .. 2^64-1 on the command line as in the config") {
  for (const std::string bad : {"-1", "18446744073709551616", "1e3", "7.5"}) {
    CHECK(build_error(edited("seed: 7", "seed: " + bad)) == cfg_path() + ":2:7: seed: expected an integer 0 .. 2^64-1, got '" + bad + "'");
    const auto [rc, out] = fly_cli({"--seed", bad});
    CHECK(rc != 0);
    CHECK(out == "tern: error: --seed: '" + bad + "' is not a seed: an integer 0 .. 2^64-1 (see --help)\n");
  }
  CHECK(build_error(edited("seed: 7", "seed: 18446744073709551615")) == "");
  const tern::core::FlightResult r = fly_yaml(edited("duration: 2", "duration: 0.1"), "seed_max", std::uint64_t{18446744073709551615ull});
  CHECK(read_file(r.run_dir / "config.yaml").find("\nseed: 18446744073709551615\n") != std::string::npos);
}

TEST_CASE("names: instances are identifiers, the mission's name cannot leave the log directory") {
  CHECK(build_error(edited("name: sensor", "name: ../../escape")) ==
        cfg_path() + ":6:12: plugins[0].name: '../../escape' is not an identifier (letters, digits and '_', not starting with a digit)");
  CHECK(build_error(edited("name: sensor", "name: 2nd")).find("plugins[0].name: '2nd' is not an identifier") != std::string::npos);
  CHECK(build_error(edited("name: hostcheck", "name: ../../escape")) ==
        cfg_path() + ":1:7: name: '../../escape' must be letters, digits, '_', '-' and '.' (not first): it names the run directory");
  CHECK(build_error(edited("name: hostcheck", "name: .hidden")).find("name: '.hidden' must be") != std::string::npos);
  CHECK(build_error(edited("name: hostcheck", "name: flight-2.b")) == "");
}

TEST_CASE("log settings name topics that exist") {
  CHECK(build_error(edited("log: {max_rate: 0}", "log: {max_rate: 0, rates: {imu: 0, acutators: 10}}")) ==
        cfg_path() + ":4:36: log.rates.acutators: no instance publishes topic 'acutators' (did you mean 'actuators'?)");
  CHECK(build_error(edited("log: {max_rate: 0}", "log: {topics: [imu, stat]}")) ==
        cfg_path() + ":4:21: log.topics[1]: no instance publishes topic 'stat' (did you mean 'state'?)");
  CHECK(build_error(edited("log: {max_rate: 0}", "log: {topics: [imu, state], rates: {imu: 10}}")) == "");
}

TEST_CASE("a start-only parameter is refused in flight ('takes effect next flight') and set before the next start") {
  tern::core::HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / "start_only";
  tern::core::Host h(tern::core::load_config(write_file("start_only.yaml", base_config())), o);
  h.build();
  std::string refused;
  const int observer = h.add_tick_observer([&](tern::Nanos now) {
    if (now != 1'000'000'000) return;
    h.request_param("ctl.kp", 0.06, "dds");  // a live one is taken in flight
    try {
      h.request_param("sensor.h0", 5.0, "dds");
    } catch (const tern::ParamError& e) {
      refused = e.what();
    }
  });
  const auto first = h.fly();
  CHECK(refused ==
        "parameter 'sensor.h0' is read when a flight starts: refused in flight, it takes effect next flight (set it between flights)");
  const std::string params1 = read_file(first.run_dir / "params.csv");
  CHECK(params1.find("\n1.002500000,ctl.kp,0.06,dds\n") != std::string::npos);
  CHECK(params1.find("sensor.h0,5") == std::string::npos);
  h.remove_tick_observer(observer);
  h.request_param("sensor.h0", 7.0, "dds");  // between flights: the sensor starts from it
  const auto second = h.fly();
  CHECK(read_file(second.run_dir / "params.csv").find("\n0.000000000,sensor.h0,7,dds\n") != std::string::npos);
  CHECK(cells(lines(read_file(second.run_dir / "topics" / "truth.csv"))[1])[4] == "-7");
}

TEST_CASE("check: the mission check's distance limit is a positive number of metres; its keys are checked") {
  CHECK(build_error(base_config("", "check: {max_waypoint_distance: 2000}\n")) == "");
  CHECK(build_error(base_config("", "check: {max_waypoint_distance: -1}\n")) ==
        cfg_path() + ":5:32: check.max_waypoint_distance: must be > 0 m, got -1");
  CHECK(build_error(base_config("", "check: {max_waypoint_distanse: 1}\n")) ==
        cfg_path() + ":5:9: check: unknown key 'max_waypoint_distanse' (did you mean 'max_waypoint_distance'?)");
}

TEST_CASE("what a vehicle sends reaches the terminal escaped, its line ends kept (tern echo, topics, param, mission)") {
  using tern::core::terminal_text;
  CHECK(terminal_text("phase: \x1b]0;owned\x07"
                      "cruise\nVa: 17\n") == "phase: \\x1b]0;owned\\x07cruise\nVa: 17\n");
  CHECK(terminal_text("a\r\nb") == "a\\r\nb");
  CHECK(terminal_text(std::string(500, 'x')) == std::string(500, 'x'));  // nothing cut
  CHECK(terminal_text("") == "");
}
