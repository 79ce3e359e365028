// core/apps/import/sensor_log_notes.hpp: how `tern import` keeps its warnings in a sensor log's
// sensor_log.yaml (docs/sensor-log.md, notes), so that the log says later what the import said once.
#pragma once

#include <string_view>

namespace tern::core {

/// The start of a note in sensor_log.yaml that keeps one of the import's warnings
/// (SensorLogWriter::finish): what the import said of a table it did not write, read again by
/// tern sysid and tern validate when that table is missing (sysid/import_notes.hpp).
inline constexpr std::string_view kImportWarning = "import warning: ";

}  // namespace tern::core
