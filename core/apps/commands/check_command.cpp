// core/apps/commands/check_command.cpp: `tern check CONFIG`: validate a mission config and its
// waypoints without flying, and print its port graph (text, or Graphviz with --dot).
#include <cstdio>
#include <memory>

#include "commands/commands.hpp"
#include "commands/fleet_command.hpp"
#include "commands/host_preparation.hpp"
#include "tern/aircraft.hpp"

namespace tern::core {

namespace {

struct CheckOptions {
  std::string config;
  bool dot = false;
  HostPreparation prep;
};

int check(const CheckOptions& o) {
  if (is_fleet_file(o.config)) return check_fleet(o.config, o.prep);
  const std::unique_ptr<Host> host = describing_host(o.config, o.prep);
  std::fputs((o.dot ? host->graph_dot() : host->graph_text()).c_str(), stdout);
  std::fflush(stdout);
  // the aircraft file as the flight's simulator will read it (tern/aircraft.hpp: ranges, inertia)
  if (!host->config().aircraft.empty()) load_aircraft(host->config().aircraft.string());
  const bool ok = report_missions(check_missions(*host), true);
  if (ok && !o.dot) std::printf("config OK: %s\n", host->config().file.c_str());
  return ok ? 0 : 1;
}

}  // namespace

Command add_check_command(CLI::App& app) {
  auto o = std::make_shared<CheckOptions>();
  auto* c = app.add_subcommand("check", "validate a mission config and its waypoints without flying and print its port graph");
  c->add_option("config", o->config, "mission config (YAML)")->required();
  c->add_flag("--dot", o->dot, "print the port graph as Graphviz instead of text");
  add_mission_override_options(c, o->prep);
  return {c, [o] { return check(*o); }};
}

}  // namespace tern::core
