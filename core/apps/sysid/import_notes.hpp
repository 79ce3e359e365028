// core/apps/sysid/import_notes.hpp: what `tern import` said of a table when it made a sensor log
// (its warnings kept in sensor_log.yaml's notes: import/sensor_log_notes.hpp), for the error of
// tern sysid and tern validate when that table is missing.
#pragma once

#include <filesystem>
#include <string>

namespace tern::core::sysid {

/// Each note of `sensor_log_yaml` that starts with kImportWarning and names `table` (e.g.
/// "actuators.csv"), as "; sensor_log.yaml: <note>" to follow an error line, each note as
/// tern::printable shows it (one line, control characters escaped, cut to kMaxEchoChars); "" when
/// there is none, or the file is missing, beyond tern/input_file.hpp's bounds, not YAML or its notes
/// no list of strings (the error then stands on its own: never throws).
std::string import_said(const std::filesystem::path& sensor_log_yaml, const std::string& table);

}  // namespace tern::core::sysid
