// sdk/src/yaml_keys.cpp: see tern/yaml_keys.hpp.
#include "tern/yaml_keys.hpp"

#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace tern {

std::optional<RepeatedKey> repeated_key(const YAML::Node& map) {
  if (!map.IsMap()) return std::nullopt;
  std::vector<std::pair<std::string, YAML::Mark>> seen;  // a map holds tens of keys: a scan is enough
  for (const auto& kv : map) {
    if (!kv.first.IsScalar()) continue;
    for (const auto& [key, mark] : seen)
      if (key == kv.first.Scalar()) return RepeatedKey{key, mark, kv.first.Mark()};
    seen.emplace_back(kv.first.Scalar(), kv.first.Mark());
  }
  return std::nullopt;
}

}  // namespace tern
