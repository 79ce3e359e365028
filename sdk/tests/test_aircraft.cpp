// The aircraft-file reader (tern/aircraft.hpp) on both formats and on bad files.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "tern/aircraft.hpp"
#include "tern/math.hpp"

using namespace tern;

namespace {
const std::string kTern = std::string(TERN_AIRCRAFT_DIR) + "/anaconda.yaml";
const std::string kRosflight = std::string(TERN_SIM_AERO_TEST_DATA) + "/anaconda_dynamics.yaml";

/// The error message of loading `path` ("" when it loads).
std::string error_of(const std::string& path) {
  try {
    load_aircraft(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

/// anaconda.yaml with the line starting `key_line` replaced, written to a temporary file.
std::string anaconda_with(const std::string& key_line, const std::string& replacement) {
  const std::filesystem::path out = std::filesystem::temp_directory_path() / "tern_sdk_test_aircraft.yaml";
  std::ifstream in(kTern);
  std::ofstream o(out);
  for (std::string line; std::getline(in, line);) o << (line.rfind(key_line, 0) == 0 ? replacement : line) << "\n";
  return out.string();
}
}  // namespace

TEST_CASE("aircraft: tern's format and ROSflight's give the Anaconda alike") {
  const Aircraft t = load_aircraft(kTern), r = load_aircraft(kRosflight);
  for (const Aircraft* a : {&t, &r}) {
    CAPTURE(a->source);
    CHECK(a->mass == 4.5);
    CHECK(a->rho == 1.2682);
    CHECK(a->S == doctest::Approx(0.52));
    CHECK(a->aero.C_L_0 == doctest::Approx(0.506));  // ROSflight spells it C_L_O
    CHECK(a->aero.C_Y_beta == doctest::Approx(-0.98));
    CHECK(a->max_delta_a == doctest::Approx(40.0 * kRadPerDeg).epsilon(1e-6));  // ROSflight: degrees
    CHECK_FALSE(a->stall_blend);  // linear lift: the file says so, ROSflight's simulator has no other
  }
  CHECK(t.Jx == r.Jx);
  CHECK(t.Jxz == r.Jxz);
}

TEST_CASE("aircraft: a NaN names the file, the line, the field and the value") {
  const std::string f = anaconda_with("  C_L_alpha:", "  C_L_alpha: .nan");
  const std::string e = error_of(f);
  CHECK(e.rfind(f + ":", 0) == 0);
  CHECK(e.find(": aero.C_L_alpha: value .nan is not finite") != std::string::npos);
  std::filesystem::remove(f);
}

TEST_CASE("aircraft: a field or a section given twice names the second (yaml-cpp would read the first silently)") {
  const std::string f = anaconda_with("  C_L_alpha:", "  C_L_alpha: 5.0\n  C_L_alpha: 4.0");
  const std::string e = error_of(f);
  CHECK(e.rfind(f + ":", 0) == 0);
  CHECK(e.find(": aero.C_L_alpha: given twice: one of the two would be ignored") != std::string::npos);
  std::filesystem::remove(f);
  const std::string top = anaconda_with("mass:", "mass: 2\nmass: 3");
  CHECK(error_of(top).find(": mass: given twice: one of the two would be ignored") != std::string::npos);
  std::filesystem::remove(top);
}

TEST_CASE("aircraft: a word where a number belongs is refused with the word") {
  const std::string f = anaconda_with("mass:", "mass: heavy");
  CHECK(error_of(f).find("mass: expected a number, got 'heavy'") != std::string::npos);
  std::filesystem::remove(f);
}

TEST_CASE("aircraft: a missing file is one error naming it") {
  CHECK(error_of("/nonexistent/aircraft.yaml") == "/nonexistent/aircraft.yaml: cannot open aircraft file");
}

TEST_CASE("aircraft: moments of inertia that no rigid body has (the triangle inequality) name the field") {
  const std::string f = anaconda_with("  Jz:", "  Jz: 0.7");  // Jx + Jy = 0.62695 kg m^2
  const std::string e = error_of(f);
  CHECK(e.rfind(f + ": inertia.Jz: 0.7 kg m^2 exceeds Jx + Jy = 0.62695 kg m^2", 0) == 0);
  std::filesystem::remove(f);
  const std::string plate = anaconda_with("  Jz:", "  Jz: 0.62695");  // a flat plate: the limit, allowed
  CHECK(error_of(plate) == "");
  std::filesystem::remove(plate);
}

TEST_CASE("aircraft: a directory or a device given as the file is one line naming it") {
  const std::string dir = std::filesystem::temp_directory_path().string();
  CHECK(error_of(dir) == dir + ": aircraft file is a directory");
  CHECK(error_of("/dev/zero") == "/dev/zero: aircraft file is not a regular file (a character device)");
}

TEST_CASE("aircraft: a list or a map as a key, or a map as the name, is one line naming the file, line and field") {
  // fuzz_aircraft_yaml's finding: yaml-cpp's bare "bad conversion" escaped the loader, naming no file
  const std::string f = anaconda_with("  C_Q_2:", "  ? {C_Q_2: -0.011779}\n  : 1");
  const std::string e = error_of(f);
  CHECK(e.rfind(f + ":", 0) == 0);
  CHECK(e.find(": propulsion: a key is a name, got a map") != std::string::npos);
  std::filesystem::remove(f);
  const std::string top = anaconda_with("name:", "[name, x]: anaconda");
  CHECK(error_of(top).find(": (document): a key is a name, got a list") != std::string::npos);
  std::filesystem::remove(top);
  const std::string name = anaconda_with("name:", "name: {first: ana}");
  CHECK(error_of(name).find(": name: expected a name") != std::string::npos);
  std::filesystem::remove(name);
}

TEST_CASE("aircraft: a ROSflight node that is not a map, or a list as a parameter's key, names the file") {
  const std::filesystem::path out = std::filesystem::temp_directory_path() / "tern_sdk_test_rosflight.yaml";
  {
    std::ofstream o(out);
    o << "/**:\n  ros__parameters:\n    rho: 1.2682\n/fixedwing_forces_and_moments: 3\n";
  }
  CHECK(error_of(out.string()) == out.string() + ": /fixedwing_forces_and_moments: expected 'ros__parameters:' map");
  {
    std::ofstream o(out);
    o << "/**:\n  ros__parameters:\n    [rho, mass]: 1.2682\n";
  }
  CHECK(error_of(out.string()).find(": /**.ros__parameters: a key is a name, got a list") != std::string::npos);
  std::filesystem::remove(out);
}
