// core/apps/sysid/import_notes.cpp: the import's warnings read back from sensor_log.yaml (import_notes.hpp).
#include "sysid/import_notes.hpp"

#include <yaml-cpp/yaml.h>

#include "import/sensor_log_notes.hpp"
#include "tern/input_file.hpp"

namespace tern::core::sysid {

std::string import_said(const std::filesystem::path& sensor_log_yaml, const std::string& table) {
  std::string said;
  try {
    const YAML::Node notes = load_yaml_file(sensor_log_yaml, "sensor log description")["notes"];  // within its bounds, or throws
    if (!notes.IsSequence()) return "";
    for (const auto& n : notes) {
      if (!n.IsScalar()) continue;
      const std::string& text = n.Scalar();
      if (text.rfind(kImportWarning, 0) == 0 && text.find(table) != std::string::npos) said += "; sensor_log.yaml: " + printable(text);
    }
  } catch (const std::exception&) {  // YAML, too large, unreadable: the error stands on its own
    return "";
  }
  return said;
}

}  // namespace tern::core::sysid
