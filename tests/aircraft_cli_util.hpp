// tests/aircraft_cli_util.hpp: what the command-line tests of `tern sysid` and `tern validate` share:
// the run directory a quiet `tern fly` printed, an aircraft file with its coefficients scaled, and
// the check that a bad input is one error line.
#pragma once

#include <string>
#include <utility>

#include <doctest/doctest.h>
#include <yaml-cpp/yaml.h>

#include "e2e_util.hpp"
#include "test_process.hpp"

/// The run directory a quiet `tern fly` printed ("log: DIR") into `out`.
inline fs::path run_dir_of(const fs::path& out) {
  for (const auto& l : lines(read_file(out)))
    if (l.rfind("log: ", 0) == 0) return l.substr(5);
  FAIL("no 'log:' line in " << read_file(out));
  return {};
}

/// The aircraft file `source` with every aerodynamic coefficient times `factor`, written as `name`
/// in the test's directory.
inline fs::path scaled_aircraft(const std::string& source, double factor, const std::string& name) {
  YAML::Node doc = YAML::LoadFile(source);
  for (auto entry : doc["aero"]) entry.second = entry.second.as<double>() * factor;
  doc["name"] = fs::path(name).stem().string();
  YAML::Emitter e;
  e << doc;
  return write_file(name, e.c_str());
}

/// A command's (exit status, output) is exit status 1 and one line holding `what`.
inline void check_one_error_line(const std::pair<int, std::string>& r, const std::string& what) {
  INFO(r.second);
  CHECK(r.first == 1);
  const auto l = lines(r.second);
  REQUIRE(l.size() == 1);
  CHECK(l[0].find(what) != std::string::npos);
}
