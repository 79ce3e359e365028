// core/apps/commands/export_command.cpp: `tern export csv RUN` and `tern export recover RUN`, on a
// flight's MCAP log (docs/logs.md). RUN is a run directory (its flight.mcap) or an .mcap file.
//   csv      the topic tables the CSV log would have written, into RUN/topics/ (or --out DIR);
//            nothing is overwritten (export/mcap_csv_export.hpp)
//   recover  a file cut short rewritten complete, up to its last complete chunk, as
//            RUN/flight.recovered.mcap (or --out FILE) (mcap/mcap_recover.hpp)
//   plan     `tern export plan CONFIG OUT.plan`: a config's mission (or a run's config.yaml) as a
//            QGroundControl plan (commands/plan_export.hpp); OUT is not overwritten
// Prints what was written; exit status 0, or 1 with one error line.
#include <memory>

#include <fmt/format.h>

#include <fstream>

#include "commands/commands.hpp"
#include "commands/host_preparation.hpp"
#include "config/error.hpp"
#include "commands/plan_export.hpp"
#include "commands/flown_mission.hpp"
#include "export/mcap_csv_export.hpp"
#include "mcap/mcap_reader.hpp"
#include "mcap/mcap_recover.hpp"
#include "mcap/mcap_writer.hpp"

namespace tern::core {

namespace {

struct ExportOptions {
  std::string run, out;
  std::size_t chunk_size = McapWriter::Options{}.chunk_bytes;
  CLI::App* csv = nullptr;
  CLI::App* recover = nullptr;
  CLI::App* plan = nullptr;
};

fs::path mcap_of(const std::string& run) { return fs::is_directory(run) ? fs::path(run) / "flight.mcap" : fs::path(run); }
fs::path run_dir_of(const std::string& run) { return fs::is_directory(run) ? fs::path(run) : fs::path(run).parent_path(); }

int run_csv(const ExportOptions& o) {
  const fs::path out = o.out.empty() ? run_dir_of(o.run) / "topics" : fs::path(o.out);
  const CsvExportReport r = export_csv(mcap_of(o.run), out);
  fmt::print("{} -> {}/\n", mcap_of(o.run).string(), out.string());
  for (const auto& [topic, rows] : r.rows) fmt::print("  {:<24} {:>9} rows\n", topic, rows);
  for (const auto& s : r.skipped) fmt::print(stderr, "tern: warning: channel {} is not a tern topic table: skipped\n", s);
  if (!r.stopped.empty())
    fmt::print(stderr, "tern: warning: {}: {} (tern export recover completes it)\n", mcap_of(o.run).string(), r.stopped);
  return 0;
}

int run_recover(const ExportOptions& o) {
  const fs::path in = mcap_of(o.run);
  const fs::path out = o.out.empty() ? run_dir_of(o.run) / "flight.recovered.mcap" : fs::path(o.out);
  if (fs::exists(out)) return fail(fmt::format("export recover: {} exists; nothing was overwritten", out.string()));
  const RecoverReport r = recover_mcap(in, out, o.chunk_size);
  fmt::print("{} -> {}: {} messages from {} chunks, {} attachments\n", in.string(), out.string(), r.messages, r.chunks, r.attachments);
  fmt::print("{}\n", r.stopped.empty() ? "the input was complete" : "stopped: " + r.stopped);
  return 0;
}

/// The config's mission as a QGroundControl plan (plan_export.hpp); nothing is overwritten.
int run_plan(const ExportOptions& o) {
  if (fs::exists(o.out)) return fail(fmt::format("export plan: {} exists; nothing was overwritten", o.out));
  // a run directory: the mission as it flew (its log's last waypoint list), about its config's home
  const bool run_dir = fs::is_directory(o.run);
  const std::string config = run_dir ? (fs::path(o.run) / "config.yaml").string() : o.run;
  const std::optional<msg::WaypointList> flown = run_dir ? last_waypoint_list(o.run) : std::nullopt;
  if (run_dir && !flown) fmt::print("{}: the log has no waypoint list: the config's mission\n", o.run);
  const std::string text = plan_of(*describing_host(config, HostPreparation{}), flown ? &*flown : nullptr);
  std::ofstream out(o.out, std::ios::binary);
  out << text;
  out.close();
  if (!out) return fail(fmt::format("export plan: {}: cannot be written", o.out));
  if (flown)
    fmt::print("{}: the mission as flown (its last waypoint list, revision {}, t = {:.1f} s)\n", o.run, flown->revision,
               to_seconds(flown->stamp));
  fmt::print("{} -> {}\n", o.run, o.out);
  return 0;
}

int run_export(const ExportOptions& o) {
  try {
    if (o.plan->parsed()) return run_plan(o);
    return o.csv->parsed() ? run_csv(o) : run_recover(o);
  } catch (const McapError& e) {
    return fail(fmt::format("export: {}", e.what()));
  } catch (const ConfigError& e) {
    return fail(fmt::format("export plan: {}", e.what()));
  }
}

}  // namespace

Command add_export_command(CLI::App& app) {
  auto o = std::make_shared<ExportOptions>();
  auto* c = app.add_subcommand(
      "export", "a flight's MCAP log as CSV tables, or recovered after a killed flight (docs/logs.md); a mission as a QGroundControl plan");
  c->require_subcommand(1);
  o->csv = c->add_subcommand("csv", "write the topic tables the CSV log would have written (RUN/topics/*.csv)");
  o->csv->add_option("run", o->run, "run directory (its flight.mcap) or an .mcap file")->required();
  o->csv->add_option("--out", o->out, "directory of the tables (default RUN/topics; existing tables are not overwritten)");
  o->recover = c->add_subcommand("recover", "rewrite a file cut short (no summary) complete, up to its last complete chunk");
  o->recover->add_option("run", o->run, "run directory (its flight.mcap) or an .mcap file")->required();
  o->recover->add_option("--out", o->out, "file to write (default RUN/flight.recovered.mcap)");
  o->recover->add_option("--chunk-size", o->chunk_size, "bytes of messages per chunk (default: the log's, 1 MiB)")
      ->check(CLI::Range(1024, 1 << 30));
  o->plan = c->add_subcommand("plan",
                              "write a mission config's mission (a run's: as it flew), geofence and rally points as a QGroundControl plan");
  o->plan->add_option("config", o->run, "mission config, or a run directory (the mission as its log says it flew)")->required();
  o->plan->add_option("out", o->out, "the .plan file to write")->required();
  return {c, [o] { return run_export(*o); }};
}

}  // namespace tern::core
