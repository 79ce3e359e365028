// The commands' timing in a flight's series (flight_data.hpp) when the log is slower than the
// controller: an IMU logged at 50 Hz, commands logged at 10 Hz (issue 76: logs from other
// autopilots), on tables whose answers are known.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "config/error.hpp"
#include "sysid/flight_data.hpp"
#include "tern/math.hpp"

using namespace tern::core::sysid;

namespace {

// A table of `n` rows at `hz` from t = 0: each named column filled by f(name, t).
template <std::size_t N>
tern::core::CsvTable table(double hz, std::size_t n, const std::array<const char*, N>& names,
                           const std::function<double(const std::string&, double)>& f) {
  tern::core::CsvTable c;
  c.file = "synthetic.csv";
  c.rows = n;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) / hz;
    c.columns["t"].push_back(t);
    for (const auto& name : names) c.columns[name].push_back(f(name, t));
  }
  return c;
}

// A still, level flight's tables (IMU at imu_hz, the estimate at 100 Hz) with the actuators'
// aileron `delta_a(t)` logged at act_hz.
FlightTables flight(double imu_hz, double act_hz, const std::function<double(double)>& delta_a, double seconds = 10.0) {
  FlightTables f;
  f.imu = table(imu_hz, static_cast<std::size_t>(seconds * imu_hz), kImuColumns,
                [](const std::string& n, double) { return n == "accel_z" ? -tern::kStandardGravity : 0.0; });
  f.actuators = table(act_hz, static_cast<std::size_t>(seconds * act_hz), kCommandColumns,
                      [&](const std::string& n, double t) { return n == "delta_a" ? delta_a(t) : 0.0; });
  f.state = table(100.0, static_cast<std::size_t>(seconds * 100.0), kStateColumns, [](const std::string& n, double) {
    return n == "valid" ? 1.0 : n == "Va" || n == "u" ? 20.0 : 0.0;
  });
  return f;
}

// The series of a flight whose table stops for 3 to 6 s (unfiltered, undecimated): checks that its
// samples are left out more than 1 s into the stop, and kept elsewhere (a 0.5-s stop among them).
FlightSeries without_3_to_6_s(const FlightTables& f) {
  FlightSeriesOptions o;
  o.rate_hz = 0.0, o.filter_hz = 0.0;
  FlightSeries s = series_from_tables(f, o);
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double t = s.t[k];
    if (t > 4.05 && t < 5.95) CHECK_MESSAGE(s.valid[k] == 0, "t = ", t);
    if ((t > 1.0 && t < 3.9) || (t > 6.1 && t < 9.5)) CHECK_MESSAGE(s.valid[k] == 1, "t = ", t);
  }
  return s;
}

/// The ConfigError series_from_tables throws for `f` (its message); fails the test when it throws none.
std::string refusal(const FlightTables& f, const FlightSeriesOptions& o = {}) {
  try {
    (void)series_from_tables(f, o);
  } catch (const tern::core::ConfigError& e) {
    return e.what();
  }
  FAIL("expected a ConfigError");
  return "";
}

}  // namespace

TEST_CASE("a command between two samples of a 50-Hz IMU takes effect when it was stamped, not at the next IMU sample") {
  // the aileron's 400-Hz row at 5.0125 s steps it, between the IMU's samples at 5.00 and 5.02 s:
  // over 5.00-5.04 s it is 1 for 0.6875 of the time. The series unfiltered and undecimated, on
  // its base: a 5-ms base samples that within one step (0.625); the IMU's 20-ms one gave 0.5.
  FlightSeriesOptions o;
  o.rate_hz = 0.0, o.filter_hz = 0.0;
  const double step_s = 5.0125;
  const FlightSeries s = series_from_tables(flight(50.0, 400.0, [&](double t) { return t >= step_s - 1e-9 ? 1.0 : 0.0; }), o);
  CHECK(s.t[1] - s.t[0] == doctest::Approx(0.005));
  double sum = 0.0;
  int n = 0;
  for (std::size_t k = 0; k < s.t.size(); ++k)
    if (s.t[k] >= 5.0 - 1e-9 && s.t[k] < 5.04 - 1e-9) sum += s.delta_a[k], ++n;
  CHECK(std::abs(sum / n - 0.6875) <= 0.0625 + 1e-9);
  o.rate_hz = 50.0, o.filter_hz = 10.0;  // decimated, the series keeps the IMU's 50-Hz samples' times
  const FlightSeries d = series_from_tables(flight(50.0, 400.0, [&](double t) { return t >= step_s - 1e-9 ? 1.0 : 0.0; }), o);
  CHECK(d.t[1] == doctest::Approx(0.02));
  CHECK(d.t.size() == 500);
}

TEST_CASE("commands logged at 10 Hz are joined linearly, not held for 100 ms; at 100 Hz each row is held") {
  FlightSeriesOptions o;
  const auto ramp = [](double t) { return 0.1 * t; };  // rad: a slow ramp the controller computed at its own rate
  const FlightSeries sampled = series_from_tables(flight(200.0, 10.0, ramp), o);
  const FlightSeries every = series_from_tables(flight(200.0, 100.0, ramp), o);
  double worst_sampled = 0.0, worst_every = 0.0;
  for (std::size_t k = 0; k < sampled.t.size(); ++k) {
    if (sampled.t[k] < 2.0 || sampled.t[k] > 8.0) continue;  // the filter's ends aside
    worst_sampled = std::max(worst_sampled, std::abs(sampled.delta_a[k] - ramp(sampled.t[k])));
    worst_every = std::max(worst_every, std::abs(every.delta_a[k] - ramp(every.t[k]) + 0.1 * 0.005));
  }
  CHECK(worst_sampled < 1e-3);  // held, the 10-Hz rows lag the ramp by 0.005 rad on average
  CHECK(worst_every < 1e-3);    // 100-Hz rows held: the ramp half a row (5 ms) late
  bool noted = false;
  for (const auto& n : sampled.notes) noted = noted || n.find("commands logged every 100 ms") != std::string::npos;
  CHECK(noted);
}

TEST_CASE(
    "hostile tables: IMU rows seconds apart are not interpolated; a command row stamped NaN or going back is dropped, not holding the "
    "rest") {
  FlightSeriesOptions o;
  o.rate_hz = 0.0;
  // the IMU at 0.5 Hz (rows 2 s apart, beyond the 1-s gap): the series keeps its rows, no factor of 400
  const FlightSeries sparse = series_from_tables(flight(0.5, 10.0, [](double t) { return 0.1 * t; }), o);
  CHECK(sparse.t.size() == 5);
  // commands at 10 Hz (joined): the row at 5.0 s repeated on its stamp with another value, the
  // row at 6.0 s stamped NaN, the one at 7.0 s stamped 1 s back, a NaN command at 8.0 s
  FlightTables f = flight(200.0, 10.0, [](double t) { return 0.1 * t; });
  auto& act = f.actuators;
  for (auto& [name, col] : act.columns) col.insert(col.begin() + 51, name == "delta_a" ? 0.9 : col[50]);
  ++act.rows;
  act.columns.at("t")[61] = std::nan("");
  act.columns.at("t")[71] -= 1.0;
  act.columns.at("delta_a")[81] = std::nan("");
  const FlightSeries s = series_from_tables(f, o);
  bool finite = true;
  double at_9 = std::nan("");
  for (std::size_t k = 0; k < s.t.size(); ++k) {
    finite = finite && std::isfinite(s.delta_a[k]);
    if (std::abs(s.t[k] - 9.0) < 1e-9) at_9 = s.delta_a[k];
  }
  CHECK(finite);
  CHECK(at_9 == doctest::Approx(0.9).epsilon(1e-3));  // the ramp after them (a NaN stamp froze it at 0.5 before)
  int noted = 0;
  for (const auto& n : s.notes)
    noted += n.find("2 of 101 rows whose time is not a number or goes back: dropped") != std::string::npos ||
             n.find("not a number: the row before each held") != std::string::npos;
  CHECK(noted == 2);
}

TEST_CASE("an aileron channel that is a number in no row is refused, not taken for a still surface") {
  FlightTables f = flight(200.0, 100.0, [](double) { return std::nan(""); });
  CHECK(refusal(f).find("synthetic.csv: delta_a is a number in none of its 1000 rows") != std::string::npos);
  // a flying wing's rudder, logged as 0: a surface that never moved, accepted
  f = flight(200.0, 100.0, [](double t) { return 0.05 * std::sin(t); });
  CHECK_NOTHROW((void)series_from_tables(f, FlightSeriesOptions{}));
}

TEST_CASE("an accelerometer whose z points up (FLU, ROS's base_link) is refused; FRD passes") {
  FlightTables f = flight(200.0, 100.0, [](double) { return 0.0; });
  for (double& a : f.imu.columns["accel_z"]) a = -a;  // +g at rest
  CHECK(refusal(f).find(fmt::format("synthetic.csv: accel_z's median is {:+.2f} m/s^2: an FRD accelerometer reads about {:.1f} on z",
                                    tern::kStandardGravity, -tern::kStandardGravity)) != std::string::npos);
  // the same log with its mounting given (rolled 180 deg) passes
  FlightSeriesOptions o;
  o.imu_mount = Eigen::Vector3d(tern::kPi, 0.0, 0.0);
  CHECK_NOTHROW((void)series_from_tables(f, o));
}

TEST_CASE("an accelerometer in g or in mg, or with gravity taken out, is refused, naming the median it read") {
  for (const double unit : {1.0 / tern::kStandardGravity, 1000.0 / tern::kStandardGravity}) {
    FlightTables f = flight(200.0, 100.0, [](double) { return 0.0; });
    for (double& a : f.imu.columns["accel_z"]) a *= unit;
    const std::string median = fmt::format("{:.4g}", tern::kStandardGravity * unit);  // "1", "1000"
    CHECK(refusal(f).find("synthetic.csv: the specific force's median magnitude is " + median + " m/s^2") != std::string::npos);
    CHECK(refusal(f).find(unit < 1.0 ? "g logged as m/s^2?" : "mg or cm/s^2 logged as m/s^2?") != std::string::npos);
  }
  FlightTables f = flight(200.0, 100.0, [](double) { return 0.0; });
  for (double& a : f.imu.columns["accel_z"]) a += tern::kStandardGravity;  // a linear acceleration: level flight reads 0
  CHECK(refusal(f).find("gravity taken out (a linear acceleration)?") != std::string::npos);
}

TEST_CASE("gyros logged in deg/s are refused; rad/s at an aerobatic rate passes") {
  FlightTables f = flight(200.0, 100.0, [](double) { return 0.0; });
  auto& p = f.imu.columns["gyro_x"];
  for (std::size_t k = 0; k < p.size(); ++k) p[k] = 1.5 * std::sin(0.1 * static_cast<double>(k));  // rolls: 1.06 rad/s RMS
  CHECK_NOTHROW((void)series_from_tables(f, FlightSeriesOptions{}));
  for (double& v : p) v /= tern::kRadPerDeg;  // the same in deg/s: 61 "rad/s" RMS
  CHECK(refusal(f).find("synthetic.csv: the gyros' RMS rate is 60.8 rad/s") != std::string::npos);
}

TEST_CASE("commands in another unit are refused: surfaces in degrees, the throttle in percent or microseconds") {
  // a 20-deg aileron doublet logged in degrees under delta_a [rad]
  FlightTables f = flight(200.0, 100.0, [](double t) { return t > 5.0 && t < 6.0 ? 20.0 : 0.5; });
  CHECK(refusal(f).find(fmt::format("synthetic.csv: delta_a is 20 rad at t = 5.01 s: a surface deflects less than {:.4g} rad",
                                    tern::kPi / 2.0)) != std::string::npos);
  for (const double throttle : {62.0, 1540.0}) {  // percent, a pulse width
    f = flight(200.0, 100.0, [](double) { return 0.0; });
    f.actuators.columns["delta_t"].assign(f.actuators.rows, throttle);
    CHECK(refusal(f).find(fmt::format("synthetic.csv: delta_t is {:g} at t = 0 s: the throttle is 0 (idle) .. 1 (full)", throttle)) !=
          std::string::npos);
  }
  // the documented ranges pass: a 1.5-rad surface, the throttle 0 .. 1
  f = flight(200.0, 100.0, [](double t) { return t < 1.0 ? 1.5 : -1.5; });
  f.actuators.columns["delta_t"].assign(f.actuators.rows, 1.0);
  CHECK_NOTHROW((void)series_from_tables(f, FlightSeriesOptions{}));
}

TEST_CASE("a command held over rows that are not numbers for more than 1 s leaves its samples out; a short run is held") {
  // delta_a not a number from 3 to 6 s (a dropped channel) and from 8.0 to 8.5 s (a glitch)
  const FlightTables f = flight(200.0, 100.0, [](double t) { return (t > 3.0 && t < 6.0) || (t > 8.0 && t < 8.5) ? std::nan("") : 0.01; });
  const FlightSeries s = without_3_to_6_s(f);
  bool noted = false;
  for (const auto& n : s.notes) noted = noted || n.find("there last logged more than 1 s before") != std::string::npos;
  CHECK(noted);
}

TEST_CASE("a pitot whose rows stop for more than 1 s leaves those samples out, not its last pressure held") {
  FlightTables f = flight(200.0, 100.0, [](double) { return 0.01; });
  const std::array<const char*, 1> pressure = {"pressure"};
  tern::core::CsvTable dp = table(50.0, 500, pressure, [](const std::string&, double) { return 245.0; });  // Pa: 20 m/s
  tern::core::CsvTable gap;  // no rows from 3 to 6 s: the pitot's channel dropped
  gap.file = dp.file;
  for (std::size_t k = 0; k < dp.rows; ++k) {
    const double t = dp.columns["t"][k];
    if (t > 3.0 && t < 6.0) continue;
    gap.columns["t"].push_back(t), gap.columns["pressure"].push_back(dp.columns["pressure"][k]), ++gap.rows;
  }
  f.diff_pressure = gap;
  const FlightSeries s = without_3_to_6_s(f);
}

TEST_CASE("the servo lag answers a command from its own instant: a delay below the IMU's interval moves the deflection by itself") {
  // the aileron steps to 1 at 5.0 s (a 100-Hz row); the prior's servo lags 20 ms; the IMU at 400 Hz
  // (2.5-ms samples). Each delay from 0 to 2.5 ms puts the step between the same two samples; the
  // deflection is 1 - exp(-(t - 5.0 - delay) / tau) at every sample after it, to rounding. Solved
  // on the samples' grid the lag started at the next sample's instant with the whole interval's
  // response: the 0.5-, 1.5- and 2.4-ms delays gave one series.
  const double tau = 0.02, step_s = 5.0;
  for (const double delay : {0.0, 0.0005, 0.0015, 0.0024, 0.004}) {
    FlightSeriesOptions o;
    o.rate_hz = 0.0, o.filter_hz = 0.0, o.servo_tau = tau;
    o.command_delay_s = {delay, 0.0, 0.0};
    const FlightSeries s = series_from_tables(flight(400.0, 100.0, [&](double t) { return t >= step_s - 1e-9 ? 1.0 : 0.0; }), o);
    double worst = 0.0;
    for (std::size_t k = 0; k < s.t.size(); ++k) {
      const double since = s.t[k] - step_s - delay;
      const double expected = since <= 0.0 ? 0.0 : 1.0 - std::exp(-since / tau);
      worst = std::max(worst, std::abs(s.delta_a[k] - expected));
    }
    CHECK_MESSAGE(worst < 1e-9, "delay ", delay * 1e3, " ms");
  }
}

TEST_CASE("commands joined linearly through the servo lag: a ramp's deflection trails it by the lag's time constant, exactly") {
  // 10-Hz rows of a ramp 0.1 t (joined): through a first-order lag the deflection settles to the
  // ramp delayed by tau, 0.1 (t - tau), at every sample, not only at the rows' stamps
  FlightSeriesOptions o;
  o.rate_hz = 0.0, o.filter_hz = 0.0, o.servo_tau = 0.05;
  const FlightSeries s = series_from_tables(flight(200.0, 10.0, [](double t) { return 0.1 * t; }), o);
  double worst = 0.0;
  for (std::size_t k = 0; k < s.t.size(); ++k)
    if (s.t[k] > 2.0 && s.t[k] < 9.0) worst = std::max(worst, std::abs(s.delta_a[k] - 0.1 * (s.t[k] - 0.05)));
  CHECK(worst < 1e-9);
}
