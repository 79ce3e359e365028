// Helpers for the host tests: temporary configs and reading run directories.
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <regex>
#include <stdexcept>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "config/error.hpp"
#include "flight/host.hpp"

namespace fs = std::filesystem;

// A fresh directory per test process (mkdtemp: a PID reused by a later run never sees stale
// run directories), removed when the process exits unless TERN_KEEP_TEST_DIR is set.
inline fs::path test_dir() {
  struct Dir {
    fs::path path;
    Dir() {
      std::string tmpl = (fs::temp_directory_path() / "tern_host_tests_XXXXXX").string();
      if (::mkdtemp(tmpl.data()) == nullptr) throw std::runtime_error("mkdtemp failed in " + fs::temp_directory_path().string());
      path = tmpl;
    }
    ~Dir() {
      if (std::getenv("TERN_KEEP_TEST_DIR") != nullptr) return;
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  };
  static const Dir d;
  return d.path;
}

inline fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path p = test_dir() / name;
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  return p;
}

/// params.csv with every source that names a config file's line ("/path/x.yaml:12") read as
/// "config": two configs that differ only in their file's name or layout (an inserted line) give the
/// same values from the same kind of source.
inline std::string config_sources_neutral(const std::string& params_csv) {
  static const std::regex config_line(R"([^,\n]*\.yaml:[0-9]+)");
  return std::regex_replace(params_csv, config_line, "config");
}

/// The lines of a text (no line ends).
inline std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string l; std::getline(ss, l);) out.push_back(l);
  return out;
}

/// The comma-separated cells of one CSV row.
inline std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream ss(row);
  for (std::string c; std::getline(ss, c, ',');) out.push_back(c);
  return out;
}

inline std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The standard three-instance test flight, with `extra` appended to the instance list or the
/// document (give it correctly indented YAML).
inline std::string base_config(const std::string& plugins_extra = "", const std::string& top_extra = "") {
  return "name: hostcheck\nseed: 7\nduration: 2\nlog: {max_rate: 0}\n" + top_extra +
         "plugins:\n"
         "  - {name: sensor, plugin: test_sensor, rate: 400}\n"
         "  - {name: filter, plugin: test_filter, trigger: imu}\n"
         "  - {name: ctl, plugin: test_controller, rate: 100}\n" +
         plugins_extra;
}

/// Builds and flies `yaml` (quiet), its run directory under test_dir()/logdir.
inline tern::core::FlightResult fly_yaml(const std::string& yaml, const std::string& logdir, std::optional<std::uint64_t> seed = {},
                                         std::optional<double> duration = {}) {
  tern::core::HostOptions o;
  o.quiet = true;
  o.seed = seed;
  o.duration = duration;
  o.log_dir = test_dir() / logdir;
  tern::core::Host h(tern::core::load_config(write_file("flight.yaml", yaml)), o);
  h.build();
  return h.fly();
}

/// The one-line error that loading and building `yaml` gives ("" if none).
inline std::string build_error(const std::string& yaml, const std::string& file = "cfg.yaml") {
  const fs::path p = write_file(file, yaml);
  try {
    tern::core::HostOptions o;
    o.describing = true;
    o.quiet = true;
    tern::core::Host h(tern::core::load_config(p), o);
    h.build();
  } catch (const tern::core::ConfigError& e) {
    return e.what();
  }
  return "";
}
