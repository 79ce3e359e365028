// End to end, issue 18 item 3: the failsafes on the default mission (seed 3), and a mission file
// with loiter and return_home items. Each flight is the shipped default mission with one edit;
// the checks read the flown track (the estimate, state.csv; the truth, truth.csv) against the
// orbit the path manager was given (current_path.csv).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "e2e_util.hpp"

using namespace tern::core;

namespace {

constexpr std::uint64_t kSeed = 3;

/// One topic's CSV as columns by name ("t [s]", "p_n [m]", ...).
struct Csv {
  std::map<std::string, std::vector<double>> col;
  explicit Csv(const fs::path& file) {
    const auto rows = lines(read_file(file));
    REQUIRE(rows.size() > 1);
    const auto header = cells(rows[0]);
    for (std::size_t k = 1; k < rows.size(); ++k) {
      const auto c = cells(rows[k]);
      for (std::size_t i = 0; i < header.size() && i < c.size(); ++i) col[header[i]].push_back(std::atof(c[i].c_str()));
    }
  }
  const std::vector<double>& operator[](const std::string& name) const {
    const auto it = col.find(name);
    if (it == col.end()) throw std::runtime_error("no column '" + name + "'");
    return it->second;
  }
  /// The number of rows before flight time t (s): the end of the rows [at(t0), rows_before(t1)).
  std::size_t rows_before(double t) const {
    const auto& ts = (*this)["t [s]"];
    return static_cast<std::size_t>(std::lower_bound(ts.begin(), ts.end(), t) - ts.begin());
  }
  /// The row at flight time t (s): the first at or after it. A table that ends before t has
  /// none: REQUIREd (its index would be one past the table, and reading it undefined: a flight
  /// that diverged at 90 s once "passed" a check on a row at 135 s).
  std::size_t at(double t) const {
    const std::size_t k = rows_before(t);
    REQUIRE_MESSAGE(k < (*this)["t [s]"].size(),
                    "no row at or after t = " << t << " s: the table ends at " << (*this)["t [s]"].back() << " s");
    return k;
  }
  /// REQUIREs rows up to flight time t (s): a window [t0, t] of the table is all there.
  void require_until(double t) const {
    REQUIRE_MESSAGE((*this)["t [s]"].back() >= t, "the table ends at " << (*this)["t [s]"].back() << " s, before t = " << t << " s");
  }
};

/// Horizontal distances (min, max) from (n, e) of the track in `csv` between t0 and t1 (s).
std::pair<double, double> distance_range(const Csv& csv, double n, double e, double t0, double t1) {
  csv.require_until(t1);
  double lo = 1e9, hi = 0.0;
  for (std::size_t k = csv.at(t0); k < csv.rows_before(t1); ++k) {
    const double d = std::hypot(csv["p_n [m]"][k] - n, csv["p_e [m]"][k] - e);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  return {lo, hi};
}

// The estimated track circles (n, e) at kRadius (within 20 m) between t0 and t1 (s).
constexpr double kRadius = 80.0;  // m: every failsafe and item orbit of these tests
void check_circling(const Csv& state, double n, double e, double t0, double t1, const std::string& what) {
  const auto [lo, hi] = distance_range(state, n, e, t0, t1);
  MESSAGE(what << ": distance to the orbit centre " << lo << ".." << hi << " m (radius " << kRadius << ")");
  CHECK(lo > kRadius - 20.0);
  CHECK(hi < kRadius + 20.0);
}

const nlohmann::json& event(const nlohmann::json& s, const std::string& cause) {
  for (const auto& e : s["failsafes"])
    if (e["cause"] == cause) return e;
  FAIL("no failsafe event " << cause << " in " << s["failsafes"].dump());
  return s;
}

void check_flying(const FlightResult& r) {
  CHECK(r.ok);
  const auto s = summary(r);
  CHECK(s["end_reason"] == "duration");
  CHECK(s["instances"]["sim"]["sim_crashed"].get<double>() == 0.0);
}

std::string with_failsafes(const std::string& failsafes, const std::vector<std::pair<std::string, std::string>>& more = {}) {
  auto edits = more;
  // the checks compare the estimate and the path at the failsafe's moment: every 100-Hz row
  edits.emplace_back("mission:\n", "failsafes:\n" + failsafes + "log: {level: full}\nmission:\n");
  return default_mission_with(edits);
}

// Flies `yaml` with a ground station heard every second until `heard_until` (s): the requests as
// the DDS bridge reports them (Host::ground_link_heard()), from the tick observer.
FlightResult fly_with_ground_station(const std::string& yaml, const std::string& logdir, double duration, double heard_until) {
  HostOptions o;
  o.quiet = true;
  o.seed = kSeed;
  o.duration = duration;
  o.log_dir = test_dir() / logdir;
  Host h(load_config(write_file("flight.yaml", yaml)), o);
  h.build();
  const tern::Nanos last = tern::from_seconds(heard_until);
  h.add_tick_observer([&h, last](tern::Nanos now) {
    if (now % 1'000'000'000 == 0 && now <= last) h.ground_link_heard();
  });
  return h.fly();
}

}  // namespace

TEST_CASE("issue 18: GNSS lost in cruise -> the aircraft loiters around the dead-reckoned point; GNSS back is said") {
  const std::string yaml = with_failsafes("  gnss_loss: {timeout: 3, radius: 80}\n",
                                          {{"      pitot_cover: 8.5", "      pitot_cover: 8.5\n      gnss_dropout: [100, 170]"}});
  const FlightResult r = fly_yaml(yaml, "fs_gnss", kSeed, 240.0);
  check_flying(r);
  const auto s = summary(r);
  const auto& loss = event(s, "gnss_loss");
  const double t_loss = loss["t_s"].get<double>();
  CHECK(loss["action"] == "loiter");
  CHECK(t_loss == doctest::Approx(103.0).epsilon(0.01));
  CHECK(event(s, "gnss_back")["t_s"].get<double>() > 170.0);
  const Csv state(r.run_dir / "topics" / "state.csv");
  const Csv path(r.run_dir / "topics" / "current_path.csv");
  // the orbit flown is centred on the estimate at the failsafe's moment
  const std::size_t k = path.at(t_loss + 1.0), j = state.at(t_loss);
  const double cn = path["c_n [m]"][k], ce = path["c_e [m]"][k];
  CHECK(path["rho [m]"][k] == 80.0);
  CHECK(std::hypot(cn - state["p_n [m]"][j], ce - state["p_e [m]"][j]) < 1.0);
  // from 40 s after the engagement to the end of the outage (70 s: after about 85 s of dead
  // reckoning this estimator declares itself invalid), the estimate circles at 80 m
  check_circling(state, cn, ce, t_loss + 40.0, 170.0, "GNSS loss");
  const Csv truth(r.run_dir / "topics" / "truth.csv");
  const auto [tlo, thi] = distance_range(truth, cn, ce, t_loss + 40.0, 170.0);
  MESSAGE("GNSS loss: true distance " << tlo << ".." << thi << " m (the dead-reckoned estimate drifts from the truth)");
  for (const auto& h : s["controller_handovers"])  // the estimate stayed usable: the path was flown, no recovery
    CHECK(h["to"] != "state_loss_recovery");
  CHECK(read_file(r.run_dir / "tern.log").find("failsafe gnss_loss: no valid GNSS fix for 3.0") != std::string::npos);
}

TEST_CASE("issue 18: a geofence smaller than the mission -> the aircraft returns inside and loiters at home") {
  const std::string yaml = with_failsafes("  geofence: {max_distance: 250, max_altitude: 120, radius: 80}\n");
  const FlightResult r = fly_yaml(yaml, "fs_fence", kSeed, 200.0);
  check_flying(r);
  const auto s = summary(r);
  const auto& breach = event(s, "geofence");
  const double t_breach = breach["t_s"].get<double>();
  CHECK(breach["action"] == "return_home");
  CHECK(breach["detail"].get<std::string>().find("beyond max_distance 250 m") != std::string::npos);
  const double t_inside = event(s, "geofence_inside")["t_s"].get<double>();
  MESSAGE("geofence: breached at " << t_breach << " s, inside again " << t_inside - t_breach << " s later");
  CHECK(t_inside - t_breach < 30.0);
  const Csv state(r.run_dir / "topics" / "state.csv");
  const auto [out_lo, out_hi] = distance_range(state, 0.0, 0.0, t_breach, t_inside + 1.0);
  MESSAGE("geofence: farthest from home " << out_hi << " m (fence 250 m)");
  CHECK(out_hi < 320.0);
  check_circling(state, 0.0, 0.0, t_inside + 60.0, 200.0, "geofence");
  CHECK(s["failsafes"].size() == 2);  // never out again
}

TEST_CASE("issue 18: a ground station heard, then silent -> return home and loiter there") {
  const FlightResult r =
      fly_with_ground_station(with_failsafes("  link_loss: {timeout: 5, altitude: 80, radius: 80}\n"), "fs_link", 220.0, 90.0);
  check_flying(r);
  const auto s = summary(r);
  const auto& loss = event(s, "link_loss");
  CHECK(loss["action"] == "return_home");
  CHECK(loss["t_s"].get<double>() == doctest::Approx(95.0).epsilon(0.01));
  const Csv state(r.run_dir / "topics" / "state.csv");
  check_circling(state, 0.0, 0.0, 160.0, 220.0, "link loss");
  const std::size_t k = state.at(215.0);
  CHECK(-state["p_d [m]"][k] == doctest::Approx(80.0).epsilon(0.1));
}

TEST_CASE("issue 18: a mission file with loiter and return_home items is flown: waypoint, 1 turn of loiter, waypoint, home") {
  const fs::path file = write_file("loiter_mission.yaml",
                                   "loop: false\nwaypoints:\n"
                                   "  - [300, -200, -70]\n"
                                   "  - {type: loiter, ned: [300, 200, -70], radius: 90, direction: ccw, turns: 1}\n"
                                   "  - [-200, 200, -70]\n"
                                   "  - {type: return_home, altitude: 60, radius: 80}\n");
  const std::string yaml = without_landing(default_mission_with({{(kMissions / "fixedwing_mission.yaml").string(), file.string()}}));
  const FlightResult r = fly_yaml(yaml, "fs_items", kSeed, 330.0);
  check_flying(r);
  const std::string log = read_file(r.run_dir / "tern.log");
  CHECK(log.find("loiter item 1: on the orbit") != std::string::npos);
  CHECK(log.find("passed waypoint 1") != std::string::npos);
  CHECK(log.find("passed waypoint 2") != std::string::npos);
  CHECK(log.find("return_home item 3: on the orbit") != std::string::npos);
  const Csv path(r.run_dir / "topics" / "current_path.csv");
  const std::size_t last = path["t [s]"].size() - 1;
  CHECK(path["c_n [m]"][last] == 0.0);
  CHECK(path["c_e [m]"][last] == 0.0);
  CHECK(path["c_d [m]"][last] == -60.0);
  CHECK(path["lambda []"][last] == 1.0);
  const Csv state(r.run_dir / "topics" / "state.csv");
  check_circling(state, 0.0, 0.0, 300.0, 330.0, "mission items");
}

TEST_CASE(
    "issue 18: the link still lost terminate.after s after the return home -> flight termination (glide): motor off, surfaces neutral") {
  const FlightResult r = fly_with_ground_station(with_failsafes("  link_loss: {timeout: 5, terminate: {after: 10, action: glide}}\n"),
                                                 "fs_terminate", 200.0, 60.0);
  const auto s = summary(r);
  const double t_term = event(s, "terminate")["t_s"].get<double>();
  CHECK(t_term - event(s, "link_loss")["t_s"].get<double>() == doctest::Approx(10.0).epsilon(0.001));
  const Csv act(r.run_dir / "topics" / "actuators.csv");
  const std::size_t k0 = act.at(t_term + 0.1);
  REQUIRE(k0 + 1 < act["t [s]"].size());
  bool held = true;
  for (std::size_t k = k0; k < act["t [s]"].size(); ++k)
    held = held && act["delta_t []"][k] == 0.0 && act["delta_e [rad]"][k] == 0.0 && act["delta_a [rad]"][k] == 0.0;
  CHECK(held);
  // the unpowered glide ends on the ground, and sim_aero says how: seed 3 banks into the ground
  // 16.4 s after the termination from 70 m, a wing tip first (a crash). Before the Dryden filters
  // ran in eddy time (sim_aero wind.hpp) its side gust grew without bound in the last metres, the
  // simulation diverged at 90.47 s and this check read a row 45 s past the end of the table.
  const auto& sim = s["instances"]["sim"];
  MESSAGE("termination at " << t_term << " s; end_reason " << r.end_reason << "; impact at " << sim.value("impact_t_s", -1.0) << " s, sink "
                            << sim.value("impact_sink_rate_mps", -1.0) << " m/s");
  CHECK(r.end_reason.find("error") == std::string::npos);  // "sim.step threw ... diverged": never
  CHECK(r.end_reason == s["end_reason"].get<std::string>());
  const Csv truth(r.run_dir / "topics" / "truth.csv");
  const std::size_t last = truth["t [s]"].size() - 1;
  const double h_end = -truth["p_d [m]"][last];
  bool finite = true;
  for (const char* c : {"p_n [m]", "p_e [m]", "p_d [m]", "u [m/s]", "v [m/s]", "w [m/s]"})
    for (std::size_t k = truth.at(t_term); k <= last; ++k) finite = finite && std::isfinite(truth[c][k]);
  CHECK(finite);
  CHECK(truth["Va [m/s]"][last] < 30.0);  // a glide's speed at the end, not a diverging state
  if (s["end_reason"] == "crash") {       // it struck the ground: sim_aero froze it there
    CHECK(sim["sim_crashed"].get<double>() == 1.0);
    CHECK(sim["impact_t_s"].get<double>() > t_term);
    CHECK(r.end_detail.find("the aircraft hit the ground") != std::string::npos);  // what struck, how fast: said
    CHECK(h_end < 1.0);
  } else {  // it landed: on its wheels, stopped (end_reason "landed") or rolling at the duration's end
    CHECK(sim["sim_crashed"].get<double>() == 0.0);
    CHECK(h_end < 0.5);
    CHECK(-truth["p_d [m]"][truth.at(truth["t [s]"][last] - 5.0)] < 0.5);
  }
}
