// End to end: configs/missions/sysid.yaml, the excitation manoeuvres of the signal generator's
// surface mode on the Aerosonde: it lands, every manoeuvre is flown and logged, the aircraft
// responds (roll and pitch rates), and an envelope too tight for the manoeuvres aborts the first
// one at once and hands control back for the rest of the flight.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "e2e_util.hpp"
#include "tern/math.hpp"

using namespace tern::core;

namespace {

/// A topic's CSV as columns by name (units stripped from the header).
struct Table {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
  std::size_t col(const std::string& n) const {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == n) return i;
    FAIL("no column " << n);
    return 0;
  }
};

Table read_table(const fs::path& file) {
  Table t;
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::stringstream h(line);
  for (std::string c; std::getline(h, c, ',');) t.names.push_back(c.substr(0, c.find(" [")));
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream s(line);
    for (std::string c; std::getline(s, c, ',');) row.push_back(std::stod(c));
    t.rows.push_back(std::move(row));
  }
  return t;
}

/// The largest |column| between t0 and t1 (s).
double peak(const Table& t, const std::string& column, double t0, double t1) {
  const std::size_t it = t.col("t"), ic = t.col(column);
  double m = 0.0;
  for (const auto& r : t.rows)
    if (r[it] >= t0 && r[it] <= t1) m = std::max(m, std::abs(r[ic]));
  return m;
}

}  // namespace

TEST_CASE("sysid.yaml: 18 manoeuvres at 20, 25 and 30 m/s, each logged, the aircraft responds, and it lands") {
  const FlightResult r = fly_mission("sysid.yaml", "e2e_sysid");
  REQUIRE(r.ok);
  const auto s = summary(r);
  CHECK(s["end_reason"] == "landed");
  CHECK(s["fallback_engaged"] == false);
  const auto& ex = s["instances"]["excite"];
  CHECK(ex["manoeuvres"].get<double>() == 18.0);
  CHECK(ex["aborts"].get<double>() == 0.0);
  const Table truth = read_table(r.run_dir / "topics" / "truth.csv");
  const Table x = read_table(r.run_dir / "topics" / "excitation.csv");
  // The list's manoeuvres in order (sysid.yaml): 0 delta_e chirp, 1 delta_a+delta_r multisine,
  // 2 delta_a 3211, 3 delta_r doublet, 4 delta_t 3211, 5 delta_e doublet; then again per airspeed.
  for (int i = 0; i < 18; ++i) {
    const double t0 = ex["m" + std::to_string(i) + "_start_s"].get<double>(), t1 = ex["m" + std::to_string(i) + "_end_s"].get<double>();
    CAPTURE(i);
    const int kind = i % 6;
    if (kind == 0) {
      CHECK(peak(x, "delta_e", t0, t1) > 0.07);
      CHECK(peak(x, "delta_a", t0, t1) == 0.0);
      CHECK(peak(truth, "q", t0, t1 + 2.0) > 10.0 * tern::kRadPerDeg);
    }
    if (kind == 1) {
      CHECK(peak(x, "delta_a", t0, t1) > 0.06);
      CHECK(peak(x, "delta_r", t0, t1) > 0.04);
      CHECK(peak(truth, "p", t0, t1 + 2.0) > 20.0 * tern::kRadPerDeg);
    }
    if (kind == 2) CHECK(peak(truth, "p", t0, t1 + 2.0) > 20.0 * tern::kRadPerDeg);
    if (kind == 4) CHECK(peak(x, "delta_t", t0, t1) == doctest::Approx(0.15));
  }
  // Outside the manoeuvres nothing is added: before the first, after the last.
  CHECK(peak(x, "delta_e", 0.0, ex["m0_start_s"].get<double>() - 0.01) == 0.0);
  CHECK(peak(x, "delta_a", ex["m17_end_s"].get<double>(), 1e6) == 0.0);
  CHECK(peak(x, "delta_e", ex["m17_end_s"].get<double>(), 1e6) == 0.0);
}

TEST_CASE("sysid.yaml with an envelope tighter than the manoeuvres: the first aborts at once, the rest of the flight passes through") {
  const std::string text = mission_with("sysid.yaml", {{"theta_max: 0.4 ", "theta_max: 0.13 "}, {"duration: 720", "duration: 200"}});
  const FlightResult r = fly_text(text, "sysid_tight.yaml", "e2e_sysid_tight", 200.0);
  REQUIRE(r.ok);
  const auto s = summary(r);
  const auto& ex = s["instances"]["excite"];
  CHECK(ex["aborts"].get<double>() == 1.0);
  CHECK(ex["manoeuvres"].get<double>() == 1.0);
  const double t_abort = ex["m0_aborted_s"].get<double>(), t_start = ex["m0_start_s"].get<double>();
  CHECK(t_abort > t_start);
  const Table x = read_table(r.run_dir / "topics" / "excitation.csv");
  CHECK(peak(x, "delta_e", t_start, t_abort - 0.01) > 0.0);
  CHECK(peak(x, "delta_e", t_abort, 1e6) == 0.0);
  CHECK(peak(x, "delta_a", t_abort, 1e6) == 0.0);
  CHECK(read_file(r.run_dir / "tern.log").find("excitation aborted in manoeuvre 0") != std::string::npos);
}

TEST_CASE("sysid.yaml with a bad manoeuvre list: one error line at the parameter it names, with its value") {
  const auto error_of = [](const std::string& from, const std::string& to) {
    const fs::path f = write_file("sysid_bad.yaml", mission_with("sysid.yaml", {{from, to}}));
    try {
      Host h(load_config(f), HostOptions{});
      h.build();
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string band = error_of("f_stop_hz: [4.0, 3.0,", "f_stop_hz: [0.1, 3.0,");
  CHECK(band.find("sysid_bad.yaml:") != std::string::npos);
  CHECK(band.find("plugins[6].params.f_stop_hz: parameter 'excite.f_stop_hz': manoeuvre 0 (delta_e chirp): f_stop_hz 0.1 must be above "
                  "f_start_hz 0.2 (Hz)") != std::string::npos);
  const std::string axis = error_of("delta_a+delta_r, delta_a,", "delta_a+delta_q, delta_a,");
  CHECK(axis.find("plugins[6].params.axis: parameter 'excite.axis': \"delta_q\": not a surface") != std::string::npos);
}

TEST_CASE("sysid.yaml with a geofence the first leg crosses: the failsafe's mission edit aborts the manoeuvre in flight") {
  const std::string text = mission_with("sysid.yaml", {{"phases: {takeoff: slc, climb: slc, cruise: slc}\n",
                                                        "phases: {takeoff: slc, climb: slc, cruise: slc}\n"
                                                        "failsafes: {geofence: {max_distance: 1200}}\n"},
                                                       {"duration: 720", "duration: 120"}});
  const FlightResult r = fly_text(text, "sysid_fence.yaml", "e2e_sysid_fence", 120.0);
  REQUIRE(r.ok);
  const auto s = summary(r);
  const auto& ex = s["instances"]["excite"];
  CHECK(ex["aborts"].get<double>() == 1.0);
  REQUIRE(ex.contains("m1_aborted_s"));
  const double t_abort = ex["m1_aborted_s"].get<double>();
  REQUIRE(s["failsafes"].size() >= 1);
  const double t_fence = s["failsafes"][0]["t_s"].get<double>();
  CHECK(s["failsafes"][0]["cause"] == "geofence");
  CHECK(t_abort >= t_fence);
  CHECK(t_abort - t_fence < 0.05);  // the edit reaches the generator at the next tick
  const Table x = read_table(r.run_dir / "topics" / "excitation.csv");
  CHECK(peak(x, "delta_a", t_abort, 1e6) == 0.0);
  CHECK(peak(x, "delta_r", t_abort, 1e6) == 0.0);
}
