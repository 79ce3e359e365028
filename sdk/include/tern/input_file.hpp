// tern/input_file.hpp: a file someone hands tern (a mission, aircraft, parameter or waypoint file, a
// sensor log's table) read without trusting it, and what a file says made safe for one line of a
// message (docs/hostile-inputs.md).
//
//   input_file_problem   why a path is not a file tern reads: a directory, not a regular file (a
//                        device such as /dev/zero, a FIFO, a socket: followed through symlinks),
//                        or larger than the limit given; "" when it is one
//   read_text_file       the whole text of a regular file of at most kMaxTextFileBytes
//   load_yaml_file       a YAML document of such a file, with at most kMaxYamlNodes nodes once its
//                        aliases are expanded (an "alias bomb" of nested anchors is refused here,
//                        before anything walks it)
//   printable            text for a terminal: control characters escaped, at most N characters
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "tern/export.hpp"

namespace YAML {
class Node;
}

namespace tern {

/// bytes: the largest YAML or text file tern reads whole (mission, aircraft, parameter and
/// waypoint files). The shipped ones are below 100 kB.
inline constexpr std::uintmax_t kMaxTextFileBytes = 16u << 20;
/// bytes: the largest table (CSV, text) tern reads row by row: a sensor log's topic, an imported
/// log's text table. A 400-Hz IMU table grows by about 200 MB an hour.
inline constexpr std::uintmax_t kMaxTableBytes = std::uintmax_t{1} << 30;
/// The most nodes a YAML file may hold once every alias is expanded (each use of an anchor counts
/// its nodes again). The shipped files hold a few thousand.
inline constexpr std::size_t kMaxYamlNodes = 100'000;
/// characters: a value or name echoed in a message is cut to this many, then "...".
inline constexpr std::size_t kMaxEchoChars = 200;

/// "" when `file` is a regular file (after symlinks) of at most `max_bytes`, else what it is:
/// "is a directory", "is not a regular file (a character device)", "does not exist",
/// "is 20000000 bytes, more than the 16777216 bytes tern reads of one".
TERN_API std::string input_file_problem(const std::filesystem::path& file, std::uintmax_t max_bytes);

/// The bytes of `file`. Throws std::runtime_error "<file>: <input_file_problem>" or
/// "<file>: cannot read: <errno text>"; `what` names the file's role ("aircraft file").
TERN_API std::string read_text_file(const std::filesystem::path& file, const char* what, std::uintmax_t max_bytes = kMaxTextFileBytes);

/// The YAML document of `file` (read_text_file's limits; a syntax error: "<file>:<line>:<col>:
/// YAML syntax error: ..."; more than kMaxYamlNodes nodes with aliases expanded: "<file>: more than
/// 100000 YAML nodes once its aliases are expanded (an alias bomb?)"). Throws std::runtime_error.
TERN_API YAML::Node load_yaml_file(const std::filesystem::path& file, const char* what);

/// Throws the same error as load_yaml_file when `root` (read from `file`) holds more than
/// kMaxYamlNodes nodes with its aliases expanded; stops counting there.
TERN_API void check_yaml_size(const YAML::Node& root, const std::filesystem::path& file);

/// `text` for one line of a terminal message: control characters (newlines, escape sequences, C1
/// controls) and bytes that are no UTF-8 character (RFC 3629) written as \n, \t, \r or \xHH, so
/// that the result is printable UTF-8; cut to `max_chars` characters followed by "..." when longer.
TERN_API std::string printable(std::string_view text, std::size_t max_chars = kMaxEchoChars);

}  // namespace tern
