// core/apps/commands/params_command.cpp: `tern params CONFIG`: every parameter of a mission with
// its value, default, unit, range and description; with --mavlink, the MAVLink parameter ids and
// types a ground station sees (mavlink/param_ids.hpp, docs/ground-station.md).
#include <memory>

#include <fmt/format.h>

#include "commands/commands.hpp"
#include "commands/host_preparation.hpp"
#include "commands/param_text.hpp"
#include "mavlink/mavlink_enums.hpp"
#include "mavlink/param_ids.hpp"

namespace tern::core {

namespace {

struct ParamsOptions {
  std::string config;
  HostPreparation prep;
  bool mavlink = false;
};

const char* mav_type_name(std::uint8_t t) {
  switch (t) {
    case mavlink::MAV_PARAM_TYPE_REAL32: return "REAL32";
    case mavlink::MAV_PARAM_TYPE_INT32: return "INT32";
    case mavlink::MAV_PARAM_TYPE_UINT8: return "UINT8";
    default: return "";
  }
}

/// `tern params CONFIG --mavlink`: index, MAVLink id, type, tern's name (the GCS's list, in order).
int mavlink_ids(const Host& host) {
  std::vector<std::pair<std::string, ParamKind>> all;
  for (const auto& [name, p] : host.parameters()) all.emplace_back(name, p->kind());
  const mavlink::ParamTable table(all);
  fmt::print("{:<6} {:<16} {:<7} {}\n", "index", "mavlink id", "type", "parameter");
  for (std::size_t i = 0; i < table.params().size(); ++i) {
    const auto& m = table.params()[i];
    fmt::print("{:<6} {:<16} {:<7} {}\n", i, m.id, mav_type_name(m.mav_type), m.qualified);
  }
  fmt::print("{} of {} parameters (text and vector ones have no MAVLink form)\n", table.params().size(), all.size());
  return 0;
}

int params(const ParamsOptions& o) {
  // the parameters only: a replay's config (configs/replay/) has no producer for its sensors
  const std::unique_ptr<Host> host = describing_host(o.config, o.prep, Producers::not_checked);
  if (o.mavlink) return mavlink_ids(*host);
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
  c->add_flag("--mavlink", o->mavlink, "the MAVLink parameter ids and types a ground station sees with --gcs (docs/ground-station.md)");
  return {c, [o] { return params(*o); }};
}

}  // namespace tern::core
