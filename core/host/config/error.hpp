// core/host/config/error.hpp: one-line errors from the outside world (config, files, plugins).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace YAML {
class Mark;
class Node;
}  // namespace YAML

namespace tern::core {

/// A problem with the mission config, a plugin or a file. what() is one line, starting with the
/// location ("file:line:col: field: ") when there is one.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// "file:line:col: " for a node of a YAML file (line and column 1-based), "file: " without mark.
std::string where(const std::filesystem::path& file, const YAML::Node& node);
std::string where(const std::filesystem::path& file, const YAML::Mark& mark);

/// A YAML boolean of a tern file: what yaml-cpp reads as one (true/false, True/FALSE, yes/no,
/// on/off: YAML 1.1's words, as ROS 2's parameter files take them too); anything else (a number,
/// a list, "maybe") throws ConfigError "file:line:col: field: expected true or false, got 'x'".
/// Every boolean setting of the mission, failsafe, DDS and campaign files is read by this one.
bool yaml_bool(const YAML::Node& node, const std::filesystem::path& file, const std::string& field);

/// Levenshtein distance, for "did you mean" suggestions.
std::size_t edit_distance(std::string_view a, std::string_view b);
/// " (did you mean 'x'?)" when a candidate is close enough, else "".
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

/// A map's key as text. A key that is no scalar (a list, a map, nothing: an anchor with no key)
/// throws ConfigError "file:line:col: field: a key is a name, got a list" (`field` empty: no
/// "field: " part), where yaml-cpp's as<std::string>() says only "bad conversion".
std::string key_name(const YAML::Node& key, const std::filesystem::path& file, const std::string& field);

/// Throws ConfigError "file:line:col: field: key 'k' given twice (first at line N): one of the two
/// would be ignored" for a key `map` holds twice (YAML forbids it, yaml-cpp keeps both and reads
/// the first; a key that is no name: key_name's).
void check_unique_keys(const YAML::Node& map, const std::filesystem::path& file, const std::string& field);

/// Throws ConfigError "file:line:col: field: unknown key 'k' (did you mean ...)" for the first key
/// of `map` not in `allowed`, and check_unique_keys' error (`field` empty: no "field: " part; a key
/// that is no name: key_name's).
void check_keys(const YAML::Node& map, const std::filesystem::path& file, const std::string& field,
                const std::vector<std::string>& allowed);

}  // namespace tern::core
