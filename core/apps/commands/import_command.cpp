// core/apps/commands/import_command.cpp: `tern import FORMAT INPUT OUT_DIR`: another project's
// flight log into a sensor log (docs/sensor-log.md) that `tern replay` reads. FORMAT names the
// converter (import/importers.hpp); INPUT is the log as shipped: a directory, or a .zip /
// .tar.gz archive (unpacked into a temporary directory, import/archive_input.hpp), or the log file
// itself (a PX4 .ulg, an ArduPilot .bin). Prints the
// rows written per topic and every warning; exit status 0, or 1 with one error line.
// The surfaces' commands (topics/actuators.csv) need the full deflections the log's normalised
// commands stand for: --max-deflection A E R (rad); --command-delay and --rc-channels as
// import/surface_commands.hpp says.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "commands/commands.hpp"
#include "import/archive_input.hpp"
#include "import/importers.hpp"
#include "tern/math.hpp"

namespace tern::core {

namespace {

using Importer = std::function<ImportReport(const fs::path&, SensorLogWriter&, const CommandMapping&)>;

/// FORMAT -> converter, in the order of --help.
const std::map<std::string, Importer>& importers() {
  static const std::map<std::string, Importer> all = {
      {"inertialnav", [](const fs::path& in, SensorLogWriter& out, const CommandMapping&) { return import_inertialnav(in, out); }},
      {"alfa", [](const fs::path& in, SensorLogWriter& out, const CommandMapping& c) { return import_alfa(in, out, c); }},
      {"ulog", [](const fs::path& in, SensorLogWriter& out, const CommandMapping& c) { return import_ulog(in, out, c); }},
      {"dataflash", [](const fs::path& in, SensorLogWriter& out, const CommandMapping& c) { return import_dataflash(in, out, c); }},
  };
  return all;
}

struct ImportOptions {
  std::string format, input, out_dir;
  std::vector<double> max_deflection;  ///< rad: aileron, elevator, rudder (empty: not stated)
  double command_delay = 0.0;
  std::vector<int> rc_channels{1, 2, 3, 4};
};

/// The options as the importers' CommandMapping; nullopt (with the error printed) if one is wrong.
std::optional<CommandMapping> command_mapping(const ImportOptions& o) {
  CommandMapping m;
  if (!o.max_deflection.empty()) {
    for (double d : o.max_deflection)
      if (!(d > 0.0 && d < kPi / 2))
        return fail(fmt::format("import: --max-deflection {}: each full deflection is in rad, above 0 and below pi/2", d)), std::nullopt;
    m.max_deflection = std::array<double, 3>{o.max_deflection[0], o.max_deflection[1], o.max_deflection[2]};
  }
  if (!std::isfinite(o.command_delay) || o.command_delay < 0.0)
    return fail(fmt::format("import: --command-delay {}: a delay in s, 0 or more", o.command_delay)), std::nullopt;
  m.command_delay = o.command_delay;
  for (std::size_t i = 0; i < 4; ++i) {
    const int ch = o.rc_channels[i];
    if (ch == 0 || std::abs(ch) > 32)
      return fail(fmt::format("import: --rc-channels: channel {} is not 1..32 (or -1..-32, reversed)", ch)), std::nullopt;
    m.rc_channels[i] = ch;
  }
  return m;
}

int run_import(const ImportOptions& o) {
  const auto it = importers().find(o.format);
  if (it == importers().end()) {
    std::string known;
    for (const auto& [name, f] : importers()) known += (known.empty() ? "" : ", ") + name;
    return fail(fmt::format("import: unknown format '{}' (known: {})", o.format, known));
  }
  const std::optional<CommandMapping> mapping = command_mapping(o);
  if (!mapping) return 1;
  std::unique_ptr<ArchiveInput> archive;
  std::error_code ec;
  const bool out_existed = fs::exists(o.out_dir, ec);
  try {
    // A PX4 .ulg is a file, not an archive: it is its own input. So is an ArduPilot DataFlash log
    // (.bin, .BIN, or any name that is no archive's: a device or FIFO is then refused as not a
    // regular file, naming it, instead of being unpacked).
    const std::string name = fs::path(o.input).filename().string();
    auto ends_with = [&](const char* s) {
      return name.size() >= std::strlen(s) && name.compare(name.size() - std::strlen(s), std::string::npos, s) == 0;
    };
    const bool archive_name = ends_with(".zip") || ends_with(".tar") || ends_with(".tar.gz") || ends_with(".tgz") ||
                              ends_with(".tar.bz2") || ends_with(".tar.xz");
    const bool log_file = (fs::is_regular_file(o.input, ec) && fs::path(o.input).extension() == ".ulg") ||
                          (o.format == "dataflash" && !fs::is_directory(o.input, ec) && !archive_name);
    if (!log_file) archive = std::make_unique<ArchiveInput>(o.input);
    SensorLogWriter out(o.out_dir);
    out.set_origin(fs::path(o.input).filename().string());
    if (archive) out.set_readable([&archive](const std::string& w) { return archive->readable(w); });
    const ImportReport report = it->second(archive ? archive->dir() : fs::path(o.input), out, *mapping);
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
  c->add_option("input", o->input, "the log as shipped: a directory, a .zip / .tar.gz archive, or a .ulg / .bin file")->required();
  c->add_option("out_dir", o->out_dir, "the sensor log to write (a new or empty directory)")->required();
  c->add_option("--max-deflection", o->max_deflection,
                "A E R: the full aileron, elevator and rudder deflections (rad) a normalised command of 1 stands for (the aircraft "
                "file's servos.max_delta_a/e/r); without them the surfaces' commands are not written")
      ->expected(3);
  c->add_option("--command-delay", o->command_delay,
                "s: a known transport delay from the logged command to the servo, added to the actuators' stamps (default 0)");
  c->add_option("--rc-channels", o->rc_channels,
                "A E T R: the servo output channels (1-based) of aileron, elevator, throttle, rudder in an ALFA rc/out table; negative: "
                "reversed (default 1 2 3 4, ArduPlane's RCMAP)")
      ->expected(4);
  return {c, [o] { return run_import(*o); }};
}

}  // namespace tern::core
