// core/apps/campaign/engines.hpp: the other places a campaign's flights can run besides local
// children (local_pool.hpp): a Dask distributed scheduler, and a Slurm job array. Both run the
// very commands the table records, so a flight's summary is the same on every engine.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "local_pool.hpp"

namespace tern::campaign {

/// Sends `jobs` to the Dask scheduler at `address` through the Python driver `driver`
/// (tern-campaign-dask, run by `python`; it needs Debian's python3-distributed), writing the
/// job list to `jobs_file`. `on_done(index, exit code)` as flights end. Throws core::ConfigError
/// when the driver cannot start or fails (its last line says why). `workers`: the scheduler's
/// worker count when the flights were sent. Returns false if interrupted.
bool run_dask(const std::vector<Job>& jobs, const std::string& address, const std::filesystem::path& python,
              const std::filesystem::path& driver, const std::filesystem::path& jobs_file,
              const std::function<void(std::size_t, int)>& on_done, int& workers);

/// Writes `<out>/commands.txt` (line k+1: flight k's command) and `<out>/slurm.sh`, a job array
/// (`sbatch --array=0-<n-1>`) whose task k runs line k+1 when flight k has no complete summary.
/// Returns the path of slurm.sh.
std::filesystem::path write_slurm(const std::vector<std::string>& commands, const std::filesystem::path& out, const std::string& name,
                                  const std::string& resume_command);

}  // namespace tern::campaign
