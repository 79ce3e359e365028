// tern/yaml_keys.hpp: a YAML map's key given twice. YAML 1.2 (section 3.2.1.1) requires a mapping's
// keys to be unique; yaml-cpp 0.7 keeps both entries and a lookup returns the first, so the second
// value would be ignored without a word. tern's readers of mission, waypoint, fleet, campaign,
// parameter and aircraft files refuse such a map with the first repeated key (docs/hostile-inputs.md).
#pragma once

#include <optional>
#include <string>

#include "tern/export.hpp"

#include <yaml-cpp/mark.h>

namespace YAML {
class Node;
}  // namespace YAML

namespace tern {

/// A key a map gives twice: its text, and where it stands first and again (yaml-cpp marks: 0-based
/// line and column).
struct RepeatedKey {
  std::string key;
  YAML::Mark first, again;
};

/// The first key of `map` that an earlier key of it repeats. Scalar keys are compared by their text;
/// a key that is no scalar is skipped (each reader refuses it itself). nullopt when every key is
/// unique, or `map` is no map.
TERN_API std::optional<RepeatedKey> repeated_key(const YAML::Node& map);

}  // namespace tern
