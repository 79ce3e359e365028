// bench_aerobatics: the estimator through aerobatics (issue 61's target: 0 resets, yaw within
// 3 deg RMS of the truth, the magnetometer fused throughout), seeds 1..N of the flight in
// tests/aerobatic_sim.hpp (rolls, loops, an Immelmann; kinematic truth through sim_aero's sensor
// models, `realistic` profile). Two receivers: the epoch reported (sim_aero's; gnss_delay 0), and
// not reported with the estimator assuming gnss_delay 0 while the receiver is 0.12 s late (a log
// without the epoch: the delay the real flight was sensitive to). --former flies the
// rules before issue 61 (mag_resume_time 0: the magnetometer off after a yaw reset for the rest
// of the flight; gnss_course_lag 0: the course compared with the yaw as it is). --gsf turns the
// yaw GSF and its disagreement reset on (gsf_max_sigma 0.15 rad, gsf_disagree_time 5 s, as the
// unit tests use them; off by default) to check it on rolls and loops. --latency S: the receiver
// S s late instead of the profile's 0.12 s (the second receiver's delay then goes unaccounted).
// Prints a table per receiver (median and worst over the seeds) and writes
// bench/results/bench_aerobatics.json (or --out FILE).
//   bench_aerobatics [--seeds N] [--former] [--gsf] [--latency S] [--out FILE]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "aerobatic_sim.hpp"

using namespace tern;
using namespace tern::ekf;
using namespace tern::ekf::test;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}
double worst(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }
double least(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end()); }

struct Column {
  std::string name;
  std::vector<double> values;
};

struct Rules {
  bool former = false, gsf = false;
  double latency = -1.0;  ///< s, the receiver's (negative: the profile's 0.12 s)
};

std::string run(const char* receiver, GnssEpoch epoch, int seeds, Rules rules) {
  const bool former = rules.former;
  std::vector<Column> c{{"yaw_rms_deg", {}}, {"yaw_max_deg", {}}, {"tilt_rms_deg", {}}, {"vel_rms_mps", {}},      {"gnss_yaw_resets", {}},
                        {"gnss_resets", {}}, {"mag_resets", {}},  {"mag_resumes", {}},  {"mag_fused_percent", {}}};
  std::printf("\n%s (%s rules), seeds 1-%d\n%5s %8s %8s %8s %8s %6s %6s %6s %7s %8s\n", receiver, former ? "former" : "issue 61", seeds,
              "seed", "yaw deg", "yaw max", "tilt deg", "vel m/s", "yawrst", "gnsrst", "magrst", "resumes", "mag %");
  for (int s = 1; s <= seeds; ++s) {
    EstimatorConfig cfg = aerobatic_config();
    if (former) {
      cfg.mag_resume_time = 0.0;
      cfg.gnss_course_lag = 0.0;
    }
    if (rules.gsf) {
      cfg.gsf_max_sigma = 0.15;
      cfg.gsf_disagree_time = 5.0;
    }
    const AerobaticResult r = fly_aerobatics(static_cast<std::uint64_t>(s), cfg, epoch, rules.latency);
    const double row[] = {r.yaw.rms() / kRadPerDeg,
                          r.yaw.max / kRadPerDeg,
                          r.tilt.rms() / kRadPerDeg,
                          r.vel.rms(),
                          static_cast<double>(r.gnss_yaw_resets),
                          static_cast<double>(r.gnss_resets),
                          static_cast<double>(r.mag_resets),
                          static_cast<double>(r.mag_resumes),
                          100.0 * r.mag_fused_fraction()};
    for (std::size_t i = 0; i < c.size(); ++i) c[i].values.push_back(row[i]);
    std::printf("%5d %8.2f %8.1f %8.2f %8.2f %6.0f %6.0f %6.0f %7.0f %8.1f\n", s, row[0], row[1], row[2], row[3], row[4], row[5], row[6],
                row[7], row[8]);
  }
  std::string j = std::string("    \"") + receiver + "\": {\n";
  for (std::size_t i = 0; i < c.size(); ++i) {
    const bool fused = c[i].name == "mag_fused_percent";  // its worst is the least
    char buf[256];
    std::snprintf(buf, sizeof buf, "      \"%s\": {\"median\": %.6g, \"worst\": %.6g}%s\n", c[i].name.c_str(), median(c[i].values),
                  fused ? least(c[i].values) : worst(c[i].values), i + 1 < c.size() ? "," : "");
    j += buf;
  }
  std::printf("%5s %8.2f %8.1f %8.2f %8.2f %6.0f %6.0f %6.0f %7.0f %8.1f\n", "worst", worst(c[0].values), worst(c[1].values),
              worst(c[2].values), worst(c[3].values), worst(c[4].values), worst(c[5].values), worst(c[6].values), worst(c[7].values),
              least(c[8].values));
  return j + "    }";
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 10;
  Rules rules;
  std::filesystem::path out = std::filesystem::path(TERN_BENCH_RESULTS_DIR) / "bench_aerobatics.json";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seeds" && i + 1 < argc) {
      seeds = std::atoi(argv[++i]);
    } else if (a == "--former") {
      rules.former = true;
    } else if (a == "--gsf") {
      rules.gsf = true;
    } else if (a == "--latency" && i + 1 < argc) {
      rules.latency = std::atof(argv[++i]);
    } else if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else {
      std::fprintf(stderr, "usage: bench_aerobatics [--seeds N] [--former] [--gsf] [--latency S] [--out FILE] (unknown argument '%s')\n",
                   a.c_str());
      return 2;
    }
  }
  if (seeds < 1) {
    std::fprintf(stderr, "bench_aerobatics: --seeds must be at least 1 (got %d)\n", seeds);
    return 2;
  }
  std::printf("bench_aerobatics: 230 s (rolls, loops, an Immelmann from 60 s), errors from 30 s, sim_aero `realistic` sensors\n");
  std::string j = "{\n  \"flight\": \"tests/aerobatic_sim.hpp aerobatic_sequence(), 230 s, errors from 30 s\",\n";
  j += "  \"sensor_profile\": \"realistic\",\n  \"seeds\": " + std::to_string(seeds) + ",\n";
  j += std::string("  \"rules\": \"") + (rules.former ? "former (mag_resume_time 0, gnss_course_lag 0)" : "issue 61 (defaults)") +
       (rules.gsf ? ", yaw GSF on (gsf_max_sigma 0.15, gsf_disagree_time 5)" : "") + "\",\n";
  j += "  \"targets\": {\"gnss_yaw_resets\": 0, \"gnss_resets\": 0, \"yaw_rms_deg\": 3.0, \"mag_fused_percent\": 100},\n";
  const std::string late = rules.latency >= 0.0 ? std::to_string(rules.latency) : std::string("0.12");
  const std::string second = "epoch not reported, gnss_delay 0 (" + late + " s late)";
  j += "  \"gnss_latency_s\": " + late + ",\n";
  j += "  \"receivers\": {\n";
  j += run("epoch reported", GnssEpoch::reported, seeds, rules) + ",\n";
  j += run(second.c_str(), GnssEpoch::assumed, seeds, rules) + "\n  }\n}\n";
  std::filesystem::create_directories(out.parent_path());
  std::ofstream(out) << j;
  std::printf("\nwrote %s\n", out.c_str());
  return 0;
}
