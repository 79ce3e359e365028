// core/apps/commands/params_command.cpp: `tern params CONFIG`: every parameter of a mission with
// its value, default, unit, range and description.
#include <memory>

#include <fmt/format.h>

#include "commands/commands.hpp"
#include "commands/host_preparation.hpp"
#include "commands/param_text.hpp"

namespace tern::core {

namespace {

struct ParamsOptions {
  std::string config;
  HostPreparation prep;
};

int params(const ParamsOptions& o) {
  // the parameters only: a replay's config (configs/replay/) has no producer for its sensors
  const std::unique_ptr<Host> host = describing_host(o.config, o.prep, Producers::not_checked);
  fmt::print("{:<34} {:<16} {:<16} {:<8} {:<20} {}\n", "parameter", "value", "default", "unit", "range", "description");
  for (const auto& [name, p] : host->parameters())
    fmt::print("{:<34} {:<16} {:<16} {:<8} {:<20} {}\n", name, to_string(p->value()), to_string(p->default_value()), p->spec().unit,
               range_text(*p), description_text(*p));
  return 0;
}

}  // namespace

Command add_params_command(CLI::App& app) {
  auto o = std::make_shared<ParamsOptions>();
  auto* c = app.add_subcommand("params", "list every parameter of a mission: value, default, unit, range, description");
  c->add_option("config", o->config, "mission config (YAML)")->required();
  add_mission_override_options(c, o->prep);
  return {c, [o] { return params(*o); }};
}

}  // namespace tern::core
