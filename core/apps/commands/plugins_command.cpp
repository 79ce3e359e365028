// core/apps/commands/plugins_command.cpp: `tern plugins [--path DIR ...]`: the plugins in the search
// path, each with its ports and parameters (as it declares them without a mission).
#include <memory>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "commands/commands.hpp"
#include "commands/param_text.hpp"
#include "config/error.hpp"
#include "graph/loader.hpp"

namespace tern::core {

namespace {

/// Context for listing a plugin's ports and parameters without a mission.
class DescribeContext final : public Context {
 public:
  const std::string& instance_name() const override { return name_; }
  std::optional<ParamValue> configured_value(const std::string&, const ParamSpec&) const override { return std::nullopt; }
  std::uint64_t seed() const override { return 1; }
  std::shared_ptr<spdlog::logger> logger() const override { return nullptr; }
  std::filesystem::path config_dir() const override { return {}; }
  const YAML::Node& mission() const override { return mission_; }
  std::filesystem::path aircraft_file() const override { return {}; }
  bool describing() const override { return true; }

 private:
  std::string name_ = "describe";
  YAML::Node mission_;
};

/// One plugin's description; a library that cannot be opened prints its error instead.
void describe_plugin(const fs::path& path) {
  try {
    auto lib = open_plugin(path);
    DescribeContext ctx;
    std::unique_ptr<Plugin> p = lib->create();
    p->attach(&ctx);
    fmt::print("\n{} ({}) - {}\n  {}\n", lib->info().name, kind_name(lib->info().kind), lib->info().description, path.string());
    try {
      p->configure();
    } catch (const std::exception& e) {
      fmt::print("  (configure failed: {})\n", e.what());
    }
    for (auto* in : p->inputs())
      fmt::print("  in  {:<22} {:<26} {}{}\n", in->name(), in->type().name, in->description(),
                 in->need() == Need::optional ? " (optional)" : "");
    for (auto* out : p->outputs()) fmt::print("  out {:<22} {:<26} {}\n", out->name(), out->type().name, out->description());
    for (auto* prm : p->params())
      fmt::print("  param {:<20} = {:<14} {:<8} {:<18} {}\n", prm->name(), to_string(prm->value()), prm->spec().unit, range_text(*prm),
                 description_text(*prm));
    p.reset();  // before the library goes
  } catch (const ConfigError& e) {
    fmt::print("\n{}: {}\n", path.string(), e.what());
  }
}

int list_plugins(const std::vector<std::string>& extra_dirs) {
  std::vector<fs::path> dirs(extra_dirs.begin(), extra_dirs.end());
  const auto search = plugin_search_path(dirs);
  const auto found = discover_plugins(search);
  fmt::print("plugin search path:\n");
  for (const auto& d : search) fmt::print("  {}\n", d.string());
  if (found.empty()) fmt::print("no plugins found\n");
  for (const auto& path : found) describe_plugin(path);
  return 0;
}

}  // namespace

Command add_plugins_command(CLI::App& app) {
  auto dirs = std::make_shared<std::vector<std::string>>();
  auto* c = app.add_subcommand("plugins", "list the plugins in the search path, with their ports and parameters");
  c->add_option("--path", *dirs, "extra plugin directories to search first");
  return {c, [dirs] { return list_plugins(*dirs); }};
}

}  // namespace tern::core
