#include "engines.hpp"

#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "config/error.hpp"

namespace tern::campaign {

namespace {

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream o(p);
  o << text;
  if (!o.flush()) throw core::ConfigError("cannot write '" + p.string() + "'");
}

}  // namespace

bool run_dask(const std::vector<Job>& jobs, const std::string& address, const std::filesystem::path& python,
              const std::filesystem::path& driver, const std::filesystem::path& jobs_file,
              const std::function<void(std::size_t, int)>& on_done, int& workers) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& job : jobs) j.push_back({{"index", job.index}, {"argv", job.argv}, {"console", job.console.string()}});
  write_text(jobs_file, j.dump(1) + "\n");
  const std::string cmd =
      fmt::format("{} {} {} {} 2>&1", quote(python.string()), quote(driver.string()), quote(address), quote(jobs_file.string()));
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) throw core::ConfigError("cannot start the Dask driver: " + cmd);
  char buf[4096];
  std::string last;
  while (std::fgets(buf, sizeof buf, p) != nullptr) {
    std::string line(buf);
    while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
    std::size_t idx = 0;
    int rc = 0;
    if (std::sscanf(line.c_str(), "done %zu %d", &idx, &rc) == 2) {
      on_done(idx, rc);
    } else if (std::sscanf(line.c_str(), "workers %d", &rc) == 1) {
      workers = rc;
    } else if (!line.empty()) {
      last = line;
    }
    if (interrupted() != 0) break;
  }
  const int status = pclose(p);
  if (interrupted() != 0) return false;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw core::ConfigError("dask: " + (last.empty() ? fmt::format("the driver {} failed (status {})", driver.string(), status) : last));
  return true;
}

std::filesystem::path write_slurm(const std::vector<std::string>& commands, const std::filesystem::path& out, const std::string& name,
                                  const std::string& resume_command) {
  std::string lines;
  for (const auto& c : commands) lines += c + "\n";
  write_text(out / "commands.txt", lines);
  const std::filesystem::path script = out / "slurm.sh";
  write_text(script, fmt::format(R"(#!/bin/bash
# Slurm job array for campaign {name}: task k flies flight k (line k+1 of commands.txt), unless
# it already has a complete summary. Submit from any directory of the cluster that shares the
# tern install and {out}:
#   sbatch --array=0-{last} {script}
# then, when the array is done, collect the table, summary and plots (nothing is re-flown):
#   {resume}
#SBATCH --job-name=tern-{name}
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=1
#SBATCH --output={out_raw}/flights/slurm-%A_%a.out
set -eu
k=${{SLURM_ARRAY_TASK_ID:?run me with sbatch --array}}
dir={out}/flights/$(printf '%05d' "$k")
if ls "$dir"/run/*/summary.json >/dev/null 2>&1 && ! grep -q '"end_reason": "SIG' "$dir"/run/*/summary.json; then exit 0; fi
rm -rf "$dir/run"
cmd=$(sed -n "$((k + 1))p" {commands})
eval "$cmd" > "$dir/fly.log" 2>&1
)",
                                 fmt::arg("name", name), fmt::arg("out", quote(out.string())), fmt::arg("out_raw", out.string()),
                                 fmt::arg("last", commands.size() - 1), fmt::arg("script", quote(script.string())),
                                 fmt::arg("resume", resume_command), fmt::arg("commands", quote((out / "commands.txt").string()))));
  std::filesystem::permissions(script, std::filesystem::perms::owner_exec | std::filesystem::perms::group_exec,
                               std::filesystem::perm_options::add);
  return script;
}

}  // namespace tern::campaign
