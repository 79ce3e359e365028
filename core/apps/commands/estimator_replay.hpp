// core/apps/commands/estimator_replay.hpp: the estimator run over a sensor log (docs/sensor-log.md),
// as `tern replay LOG` runs it, for the commands that need the estimate of a log: replay itself,
// and sysid and validate, which take attitude, wind, alpha and beta from it (the two-step method of
// system identification: the estimator, then the regression).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "flight/host.hpp"

namespace tern::core {

struct EstimatorReplay {
  std::string log_dir;                 ///< the sensor log (a tern flight log, or `tern import`'s output)
  std::string config;                  ///< empty: the log's config.yaml, else configs/replay/estimator.yaml
  std::optional<std::string> out_dir;  ///< parent of the replay's run directory (default ./runs)
  std::vector<std::string> sets;       ///< INSTANCE.PARAM=VALUE, as `tern replay --set`
  std::optional<LogLevel> level;       ///< the replay's log level (default: the config's)
  bool quiet = false;
};

/// Flies the estimator alone (no controllers, phases or mission) over the log's sensors; a log
/// written as MCAP only has its tables exported into LOG/topics first. Returns the replay's
/// FlightResult (its run_dir holds the estimate, topics/state.csv, and sensor_log.yaml copied).
/// Throws ConfigError (the config, the log's tables) as `tern replay` does.
FlightResult replay_estimator(const EstimatorReplay& req);

}  // namespace tern::core
