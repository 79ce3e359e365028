// `tern tune roll` on the default mission (the Anaconda): a table of finite, plausible step
// figures, the same output for the same seed, tune.csv for the plot; a bad loop is one error line.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_process.hpp"
#include "test_util.hpp"

namespace {
const std::string kDefault = std::string(TERN_SOURCE_DIR) + "/configs/missions/default.yaml";

/// The rows of the step table: the lines that start with a flight time.
std::vector<std::vector<double>> step_rows(const std::string& out) {
  std::vector<std::vector<double>> rows;
  for (const auto& l : lines(out)) {
    std::istringstream ss(l);
    std::vector<double> v;
    std::string cell;
    while (ss >> cell) {
      try {
        std::size_t used = 0;
        v.push_back(cell == "-" ? NAN : std::stod(cell, &used));
        if (cell != "-" && used != cell.size()) break;
      } catch (const std::exception&) {
        break;
      }
    }
    if (v.size() == 7) rows.push_back(v);
  }
  return rows;
}
std::string table_of(const std::string& out) {
  std::string t;
  for (const auto& l : lines(out))
    if (l.rfind("log:", 0) != 0 && l.rfind("plot:", 0) != 0) t += l + "\n";
  return t;
}
}  // namespace

TEST_CASE("tern tune roll: finite, plausible figures for every step, repeatable") {
  const fs::path out1 = test_dir() / "tune1.txt", out2 = test_dir() / "tune2.txt";
  REQUIRE(run_tern({"tune", "roll", "--config", kDefault, "--log-dir", (test_dir() / "runs").string(), "--no-plot"}, out1) == 0);
  const std::string text = read_file(out1);
  INFO(text);
  const auto rows = step_rows(text);
  REQUIRE(rows.size() >= 4);
  for (const auto& r : rows) {  // t, from, to, rise, overshoot, settling, ss error
    CHECK(std::abs(std::abs(r[2] - r[1]) - 0.3491) < 1e-3);
    CHECK(r[3] > 0.05);
    CHECK(r[3] < 3.0);
    CHECK(r[4] >= 0.0);
    CHECK(r[4] < 100.0);
    CHECK(std::abs(r[6]) < 0.1);  // rad: within 6 deg of the command
  }
  REQUIRE(run_tern({"tune", "roll", "--config", kDefault, "--log-dir", (test_dir() / "runs2").string(), "--no-plot"}, out2) == 0);
  CHECK(table_of(read_file(out2)) == table_of(text));
}

TEST_CASE("tern tune with an unknown loop is one error line") {
  const fs::path out = test_dir() / "tune_bad.txt";
  CHECK(run_tern({"tune", "yaw_rate", "--config", kDefault}, out) == 1);
  const auto l = lines(read_file(out));
  REQUIRE(l.size() == 1);
  CHECK(l[0].find("unknown loop 'yaw_rate'") != std::string::npos);
}
