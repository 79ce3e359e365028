// core/apps/commands/estimator_replay.hpp: the estimator run over a sensor log (docs/sensor-log.md),
// as `tern replay LOG` runs it, for the commands that need the estimate of a log: replay itself,
// and sysid and validate, which take attitude, wind, alpha and beta from it (the two-step method of
// system identification: the estimator, then the regression).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
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
  /// The estimate from kinematics alone: every estimator_ekf instance without the aircraft-model
  /// updates (use_normal_force, use_side_force false), as system identification and validation
  /// need it. Those updates turn the accelerometers into alpha and beta through the aircraft
  /// file's C_L and C_Y: the very coefficients being identified or scored (the log's file: in a
  /// simulation the world's truth, on a real aircraft the prior), so an estimate made with them
  /// hands them back. Klein and Morelli, *Aircraft System Identification*, ch. 10: the flight
  /// path is reconstructed from the kinematic equations, independently of the aerodynamic model.
  bool kinematic = false;
  /// Only the estimate: the replay logs topics/state.csv alone (with config.yaml and params.csv)
  /// and reads no truth or reference from the log, as sysid and validate need it; at level sysid
  /// the rest (the sensors and the truth written again, 400 Hz each) was most of a 600-s log's
  /// replay time and of its disk.
  bool estimate_only = false;
};

/// A flight logged as MCAP only (log.format mcap, as `make fly` writes it): its tables exported
/// into LOG/topics, as `tern export csv LOG` writes them (export/mcap_csv_export.hpp), so that the
/// replay, sysid and validate read them; one line on stderr says so. Nothing when LOG/topics exists
/// or there is no LOG/flight.mcap. Throws McapError naming the file and the field.
void tables_from_mcap(const std::filesystem::path& log_dir);

/// The estimator's replay that sysid or validate made for itself (log level sysid: the state at
/// every message, hundreds of MB for a long flight), removed when the command ends however it ends,
/// unless `keep` (--keep-estimate: --estimate takes it next time).
struct ReplayScratch {
  std::filesystem::path dir;
  bool keep = false;
  ReplayScratch(std::filesystem::path d, bool k) : dir(std::move(d)), keep(k) {}
  ReplayScratch(const ReplayScratch&) = delete;
  ReplayScratch& operator=(const ReplayScratch&) = delete;
  ~ReplayScratch() {
    std::error_code ignored;  // a directory that cannot be removed stays; nothing else depends on it
    if (!keep && !dir.empty()) std::filesystem::remove_all(dir, ignored);
  }
};

/// Flies the estimator alone (no controllers, phases or mission) over the log's sensors; a log
/// written as MCAP only has its tables exported into LOG/topics first. Returns the replay's
/// FlightResult (its run_dir holds the estimate, topics/state.csv, and sensor_log.yaml copied).
/// Throws ConfigError (the config, the log's tables) as `tern replay` does.
FlightResult replay_estimator(const EstimatorReplay& req);

}  // namespace tern::core
