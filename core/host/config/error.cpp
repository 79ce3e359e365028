#include "config/error.hpp"

#include <algorithm>

#include <yaml-cpp/yaml.h>

#include "tern/input_file.hpp"
#include "tern/yaml_keys.hpp"

namespace tern::core {

std::string where(const std::filesystem::path& file, const YAML::Mark& mark) {
  if (mark.is_null()) return file.string() + ": ";
  return file.string() + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1) + ": ";
}

std::string where(const std::filesystem::path& file, const YAML::Node& node) {
  if (!node.IsDefined()) return file.string() + ": ";
  return where(file, node.Mark());
}

bool yaml_bool(const YAML::Node& node, const std::filesystem::path& file, const std::string& field) {
  if (node.IsScalar()) {
    bool value = false;
    if (YAML::convert<bool>::decode(node, value)) return value;
  }
  const std::string got = node.IsScalar() ? node.Scalar() : node.IsMap() ? "<map>" : node.IsSequence() ? "<list>" : "<null>";
  throw ConfigError(where(file, node) + field + ": expected true or false, got '" + got + "'");
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t sub = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = std::string::npos;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
  if (best.empty()) return "";
  if (best_d > limit) {
    // a candidate contained in the word or the word in a candidate ("imu_data" -> "imu")
    best.clear();
    for (const auto& c : candidates)
      if (c.size() >= 2 && (word.find(c) != std::string_view::npos || c.find(word) != std::string::npos) &&
          (best.empty() || c.size() > best.size()))
        best = c;
    if (best.empty()) return "";
  }
  return " (did you mean '" + best + "'?)";
}

std::string key_name(const YAML::Node& key, const std::filesystem::path& file, const std::string& field) {
  if (!key.IsScalar()) {
    const char* what = key.IsSequence() ? "list" : key.IsMap() ? "map" : "null";
    throw ConfigError(where(file, key) + (field.empty() ? "" : field + ": ") + "a key is a name, got a " + what);
  }
  return key.Scalar();
}

void check_unique_keys(const YAML::Node& map, const std::filesystem::path& file, const std::string& field) {
  if (const auto r = repeated_key(map))
    throw ConfigError(where(file, r->again) + (field.empty() ? "" : field + ": ") + "key '" + printable(r->key) +
                      "' given twice (first at line " + std::to_string(r->first.line + 1) + "): one of the two would be ignored");
}

void check_keys(const YAML::Node& map, const std::filesystem::path& file, const std::string& field,
                const std::vector<std::string>& allowed) {
  check_unique_keys(map, file, field);
  for (const auto& kv : map) {
    const std::string key = key_name(kv.first, file, field);
    bool ok = false;
    for (const auto& a : allowed) ok = ok || a == key;
    if (!ok) {
      throw ConfigError(where(file, kv.first) + (field.empty() ? "" : field + ": ") + "unknown key '" + printable(key) + "'" +
                        (key.size() <= kMaxEchoChars ? did_you_mean(key, allowed) : ""));
    }
  }
}

}  // namespace tern::core
