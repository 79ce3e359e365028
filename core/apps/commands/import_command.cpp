// core/apps/commands/import_command.cpp: `tern import FORMAT INPUT OUT_DIR`: another project's
// flight log into a sensor log (docs/sensor-log.md) that `tern replay` reads. FORMAT names the
// converter (import/importers.hpp); INPUT is the log as shipped: a directory, or a .zip /
// .tar.gz archive (unpacked into a temporary directory, import/archive_input.hpp). Prints the
// rows written per topic and every warning; exit status 0, or 1 with one error line.
#include <functional>
#include <map>
#include <memory>

#include <fmt/format.h>

#include "commands/commands.hpp"
#include "import/archive_input.hpp"
#include "import/importers.hpp"

namespace tern::core {

namespace {

using Importer = std::function<ImportReport(const fs::path&, SensorLogWriter&)>;

/// FORMAT -> converter, in the order of --help.
const std::map<std::string, Importer>& importers() {
  static const std::map<std::string, Importer> all = {
      {"inertialnav", import_inertialnav},
      {"alfa", import_alfa},
      {"ulog", import_ulog},
  };
  return all;
}

struct ImportOptions {
  std::string format, input, out_dir;
};

int run_import(const ImportOptions& o) {
  const auto it = importers().find(o.format);
  if (it == importers().end()) {
    std::string known;
    for (const auto& [name, f] : importers()) known += (known.empty() ? "" : ", ") + name;
    return fail(fmt::format("import: unknown format '{}' (known: {})", o.format, known));
  }
  std::unique_ptr<ArchiveInput> archive;
  std::error_code ec;
  const bool out_existed = fs::exists(o.out_dir, ec);
  try {
    // A PX4 .ulg is a file, not an archive: it is its own input.
    const bool ulg_file = fs::is_regular_file(o.input) && fs::path(o.input).extension() == ".ulg";
    if (!ulg_file) archive = std::make_unique<ArchiveInput>(o.input);
    SensorLogWriter out(o.out_dir);
    out.set_origin(fs::path(o.input).filename().string());
    const ImportReport report = it->second(archive ? archive->dir() : fs::path(o.input), out);
    fmt::print("{} -> {}\n", o.input, o.out_dir);
    for (const auto& [topic, rows] : report.rows) fmt::print("  {:<14} {:>9} rows\n", topic, rows);
    for (const auto& w : report.warnings) fmt::print(stderr, "tern: warning: {}\n", archive ? archive->readable(w) : w);
    return 0;
  } catch (const ImportError& e) {
    if (!out_existed) fs::remove_all(o.out_dir, ec);  // no half-written sensor log left behind
    return fail(fmt::format("import: {}", archive ? archive->readable(e.what()) : std::string(e.what())));
  }
}

}  // namespace

Command add_import_command(CLI::App& app) {
  auto o = std::make_shared<ImportOptions>();
  std::string formats;
  for (const auto& [name, f] : importers()) formats += (formats.empty() ? "" : " | ") + name;
  auto* c = app.add_subcommand("import", "convert another project's flight log into a sensor log for tern replay (docs/sensor-log.md)");
  c->add_option("format", o->format, formats)->required();
  c->add_option("input", o->input, "the log as shipped: a directory, or a .zip / .tar.gz archive")->required();
  c->add_option("out_dir", o->out_dir, "the sensor log to write (a new or empty directory)")->required();
  return {c, [o] { return run_import(*o); }};
}

}  // namespace tern::core
