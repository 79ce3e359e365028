// core/host/config/cli_overrides.hpp: changes to a loaded mission config from the command line, the
// same for `tern fly`, `check`, `params`, `tune` and the benchmarks:
//   --set INSTANCE.PARAM=VALUE   a parameter, as if the config's `params:` said PARAM: VALUE
//                                (VALUE read as YAML: 0.5, true, text, [1, 2, 3]; quoted: text);
//                                INSTANCE may be phase_machine or metrics (their sections)
//   --phases PHASE=INSTANCE,...  replaces the `phases:` table (takeoff, climb, cruise required;
//                                landing, loiter optional); items may also be separate words
//   --fallback INSTANCE          the `fallback:` controller
// Applied before the host is built, so each value is checked exactly like the same value in
// the file (unknown parameter, wrong type, out of range: by the plugin when it configures);
// an error names the option and its value instead of file:line:col. The run's config.yaml
// records the effective values and names the options (config.hpp: MissionConfig::overrides).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"

namespace tern::core {

struct CliOverrides {
  std::vector<std::string> sets;    ///< "instance.param=value", as given
  std::vector<std::string> phases;  ///< "phase=instance" items, each possibly a comma-separated list
  std::optional<std::string> fallback;
  bool empty() const { return sets.empty() && phases.empty() && !fallback; }
};

/// One --set item split and read: throws ConfigError "--set 'x': ..." when it is not
/// INSTANCE.PARAM=VALUE or VALUE is not a YAML scalar or list.
struct ParamOverride {
  std::string instance, param;
  YAML::Node value;
  std::string option;  ///< "--set instance.param=value"
};
ParamOverride parse_param_override(const std::string& item);

/// PHASE=INSTANCE items (each possibly a comma-separated list) read against `config`; the same
/// reader for --phases and `tern phases`. Throws ConfigError "OPTION: ...", one line: an item that
/// is not PHASE=INSTANCE, an unknown phase or instance (with a suggestion), a phase given twice.
/// No phase is required here (--phases then requires takeoff, climb and cruise; `tern phases`
/// merges the entries into the current table); whether an instance is a controller is the router's
/// check.
std::map<msg::Phase, std::string> parse_phase_entries(const MissionConfig& config, const std::vector<std::string>& items,
                                                      const std::string& option);

/// Applies `o` to `config` (and records it in config.overrides). Throws ConfigError, one line
/// naming the option and value: unknown instance or phase (with a suggestion), a value that is
/// not YAML, a table without takeoff, climb or cruise, --fallback without a table.
void apply_overrides(MissionConfig& config, const CliOverrides& o);

}  // namespace tern::core
