// tern campaign FILE: flies a Monte Carlo campaign (campaign_file.hpp) and leaves its table,
// summary and plots (campaign_report.hpp) in the output directory. `tern campaign` runs this
// program (tern-campaign) through tern's extension commands.
//
//   1. load the campaign and its base mission; check every dispersion against the mission's
//      parameters (a describing host: plugins configured, nothing flown) and its aircraft file
//   2. write every flight's config (flight_plan.hpp); flights with a complete summary are done
//   3. fly the rest: local children (default), a Dask scheduler, or write a Slurm job array
//   4. one row per flight, the report, throughput.json, and the plots (tern-campaign-plot)
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <map>
#include <cstdio>
#include <fstream>
#include <thread>

#include <CLI/CLI.hpp>
#include <boost/dll/runtime_symbol_info.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "campaign_file.hpp"
#include "campaign_report.hpp"
#include "dispersion.hpp"
#include "engines.hpp"
#include "config/error.hpp"
#include "flight_plan.hpp"
#include "flight_row.hpp"
#include "fleet/fleet_config.hpp"
#include "flight/host.hpp"
#include "local_pool.hpp"
#include "progress.hpp"
#include "tern/aircraft.hpp"

#ifndef TERN_PYTHON3
#define TERN_PYTHON3 "/usr/bin/python3"
#endif

namespace fs = std::filesystem;
using namespace tern;
using namespace tern::campaign;

namespace {

/// Where tern-campaign is: tern, tern-campaign-dask and tern-campaign-plot sit beside it.
fs::path exe_dir() { return fs::path(boost::dll::program_location().parent_path().string()); }

double wall_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// The campaign file copied into `out`; another campaign's directory is refused.
void claim_output(const CampaignFile& c, const fs::path& out) {
  fs::create_directories(out);
  const fs::path copy = out / "campaign.yaml";
  const std::string text = read_text(c.file);
  if (fs::exists(copy) && read_text(copy) != text)
    throw core::ConfigError(
        fmt::format("{}: holds the results of a different campaign file (its campaign.yaml differs from {}): give another --out",
                    out.string(), c.file.string()));
  std::ofstream(copy) << text;
}

/// The row of flight k: its draws, and its summary's figures judged (or why it has none).
FlightRow make_row(const CampaignFile& c, const FlightDraw& d, const FlightFiles& files, int status) {
  FlightRow row;
  row.index = d.index;
  row.seed = d.seed;
  row.command = files.command;
  row.drawn = d.columns;
  const fs::path summary = finished_summary(files);
  if (summary.empty()) {
    row.outcome = Outcome::error;
    row.why = status < 0 ? fmt::format("no complete summary.json (see {})", files.console.string())
                         : fmt::format("no complete summary.json (tern fly: wait status {}; see {})", status, files.console.string());
    return row;
  }
  std::ifstream in(summary);
  row.figures = flatten_summary(nlohmann::ordered_json::parse(in));
  judge(c.criteria, row);
  return row;
}

struct Throughput {
  std::size_t flown = 0;
  double flight_s = 0, flight_wall_s = 0;  // sums over the flights flown now (timing.json)
};

void add_timing(const FlightFiles& files, Throughput& t) {
  const fs::path summary = finished_summary(files);
  if (summary.empty()) return;
  std::ifstream in(summary.parent_path() / "timing.json");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  std::ifstream sin(summary);
  const nlohmann::json s = nlohmann::json::parse(sin, nullptr, false);
  if (j.is_discarded() || s.is_discarded()) return;
  ++t.flown;
  t.flight_s += s.value("duration_s", 0.0);
  t.flight_wall_s += j.value("wall_s", 0.0);
}

void write_throughput(const fs::path& out, const std::string& engine, int workers, double wall, const Throughput& t) {
  nlohmann::ordered_json j;
  j["engine"] = engine;
  j["workers"] = workers;
  j["flights_flown"] = t.flown;
  j["wall_s"] = wall;
  j["flights_per_minute"] = wall > 0 ? 60.0 * static_cast<double>(t.flown) / wall : 0.0;
  // per core: a worker flies one flight at a time on one core; local workers beyond this machine's
  // cores share them (Dask's workers are their own cores)
  const unsigned hw = std::thread::hardware_concurrency();
  const int cores = engine == "local" && hw > 0 ? std::min(workers, static_cast<int>(hw)) : workers;
  j["cores"] = cores;
  j["flights_per_core_minute"] = wall > 0 && cores > 0 ? 60.0 * static_cast<double>(t.flown) / (wall * cores) : 0.0;
  j["flight_time_s"] = t.flight_s;
  j["aggregate_real_time_factor"] = wall > 0 ? t.flight_s / wall : 0.0;
  j["mean_flight_real_time_factor"] = t.flight_wall_s > 0 ? t.flight_s / t.flight_wall_s : 0.0;
  // worker time not spent inside a flight's own fly(): process start, plugin loading, scheduling
  const double capacity = wall * workers;
  j["overhead_fraction"] = capacity > 0 ? std::max(0.0, 1.0 - t.flight_wall_s / capacity) : 0.0;
  std::ofstream(out / "throughput.json") << j.dump(2) << "\n";
  fmt::print(
      "throughput: {} flights in {:.1f} s on {} {} worker(s): {:.1f} flights/min ({:.1f} per core-minute), {:.0f}x real time in "
      "all, {:.0f}x per flight, overhead {:.1f} %\n",
      t.flown, wall, workers, engine, j["flights_per_minute"].get<double>(), j["flights_per_core_minute"].get<double>(),
      j["aggregate_real_time_factor"].get<double>(), j["mean_flight_real_time_factor"].get<double>(),
      100 * j["overhead_fraction"].get<double>());
}

struct Options {
  std::string file, out, dask;
  int workers = 0;
  bool slurm = false, no_plots = false;
};

int run(const Options& o) {
  const CampaignFile c = load_campaign(o.file);
  core::HostOptions hopt;
  hopt.describing = true;
  hopt.quiet = true;
  // a multi-vehicle base (docs/multi-vehicle.md): the vehicles' shared stack is what is dispersed
  core::MissionConfig base = core::is_fleet_file(c.base) ? core::fleet_stack(c.base) : core::load_config(c.base);
  core::Host host(base, hopt);
  host.build();
  ParamCatalogue params;
  for (const auto& [name, p] : host.parameters()) params[name] = p;
  // The base aircraft is checked by the reader sim_aero uses (tern/aircraft.hpp: one error naming
  // the file, field and value); its YAML tree is what the dispersions perturb and each flight writes.
  if (!base.aircraft.empty()) tern::load_aircraft(base.aircraft.string());
  const YAML::Node aircraft = base.aircraft.empty() ? YAML::Node() : YAML::LoadFile(base.aircraft.string());
  const std::vector<Resolved> dispersions = resolve_dispersions(c, params, aircraft);

  const fs::path out = fs::absolute(o.out.empty() ? fs::path("campaigns") / c.name : fs::path(o.out)).lexically_normal();
  claim_output(c, out);
  const fs::path tern_bin = exe_dir() / "tern";
  std::vector<Job> pending;
  std::vector<std::string> commands;
  for (std::size_t k = 0; k < c.flights; ++k) {
    const FlightDraw d = draw_flight(c, dispersions, k);
    const FlightFiles files = flight_files(out, k, tern_bin);
    write_flight(c, base, params, aircraft, d, files);
    commands.push_back(files.command);
    if (!finished_summary(files).empty()) continue;
    std::error_code ec;
    fs::remove_all(files.run_dir, ec);  // an interrupted flight's partial log
    pending.push_back({k, files.argv, files.console});
  }
  const std::string resume = fmt::format("{} campaign {} --out {}", tern_bin.string(), c.file.string(), out.string());
  if (o.slurm) {
    const fs::path script = write_slurm(commands, out, c.name, resume);
    fmt::print("slurm: wrote {} ({} flights, {} without a summary yet)\n  submit: sbatch --array=0-{} {}\n  then collect: {}\n",
               script.string(), c.flights, pending.size(), c.flights - 1, script.string(), resume);
    return 0;
  }

  int workers = o.workers > 0 ? o.workers : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const std::string engine = o.dask.empty() ? "local" : "dask";
  Progress progress(pending.size(), c.flights - pending.size());
  std::map<std::size_t, int> statuses;  // of the flights that left no summary
  auto on_done = [&](std::size_t k, int status) {
    FlightRow row = make_row(c, draw_flight(c, dispersions, k), flight_files(out, k, tern_bin), status);
    if (row.outcome == Outcome::error) statuses[k] = status;
    progress.done(row.outcome != Outcome::pass);
  };
  install_interrupt_handlers();
  const double t0 = wall_s();
  const bool complete =
      o.dask.empty() ? run_local(pending, workers, on_done)
                     : run_dask(pending, o.dask, TERN_PYTHON3, exe_dir() / "tern-campaign-dask", out / "dask_jobs.json", on_done, workers);
  const double wall = wall_s() - t0;
  progress.finish();

  std::vector<FlightRow> rows;
  Throughput through;
  for (std::size_t k = 0; k < c.flights; ++k) {
    const FlightFiles files = flight_files(out, k, tern_bin);
    if (!complete && finished_summary(files).empty()) continue;  // interrupted: not flown yet
    const auto st = statuses.find(k);
    rows.push_back(make_row(c, draw_flight(c, dispersions, k), files, st == statuses.end() ? -1 : st->second));
  }
  for (const auto& job : pending) add_timing(flight_files(out, job.index, tern_bin), through);
  write_report(c, rows, out);
  if (!pending.empty()) write_throughput(out, engine, workers, wall, through);
  std::size_t passed = 0;
  for (const auto& r : rows) passed += r.outcome == Outcome::pass;
  const auto [lo, hi] = wilson95(passed, rows.size());
  fmt::print("campaign {}: {} of {} flights passed ({:.1f} %, 95 % CI {:.1f}-{:.1f} %)\nresults: {}\n", c.name, passed, rows.size(),
             rows.empty() ? 0.0 : 100.0 * static_cast<double>(passed) / static_cast<double>(rows.size()), 100 * lo, 100 * hi,
             (out / "summary.md").string());
  if (!complete) {
    std::fprintf(stderr, "campaign: interrupted after %zu of %zu flights; run the same command again to resume\n", rows.size(), c.flights);
    return 130;
  }
  if (!o.no_plots) {
    const std::string plot = fmt::format("{} {} {}", shell_quote(TERN_PYTHON3), shell_quote((exe_dir() / "tern-campaign-plot").string()),
                                         shell_quote(out.string()));
    if (std::system(plot.c_str()) != 0) std::fprintf(stderr, "campaign: the plots failed (%s)\n", plot.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tern campaign: fly a Monte Carlo campaign (configs/campaigns/*.yaml) and write its table, summary and plots"};
  app.name("tern campaign");
  Options o;
  app.add_option("file", o.file, "campaign file (YAML)")->required();
  app.add_option("--workers", o.workers, "flights flown at once (default: every core)")->check(CLI::Range(1, 4096));
  app.add_option("--out", o.out, "output directory (default: campaigns/<name>); rerun into it to resume");
  app.add_option("--dask", o.dask, "fly on this Dask distributed scheduler (e.g. tcp://127.0.0.1:8786; needs python3-distributed)");
  app.add_flag("--slurm", o.slurm, "write a Slurm job-array script (slurm.sh) for the flights instead of flying them");
  app.add_flag("--no-plots", o.no_plots, "skip the plots");
  app.failure_message(
      [](const CLI::App*, const CLI::Error& e) { return fmt::format("tern campaign: error: {} (see --help)\n", e.what()); });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (o.slurm && !o.dask.empty()) {
    std::fprintf(stderr, "tern campaign: error: give --dask or --slurm, not both\n");
    return 1;
  }
  try {
    return run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tern campaign: error: %s\n", e.what());
    return 1;
  }
}
