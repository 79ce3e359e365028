// core/apps/sysid/flight_data.cpp: a flight's measurements on the IMU's time base (flight_data.hpp).
#include "sysid/flight_data.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "config/error.hpp"
#include "replay/replay_csv.hpp"
#include "replay/sensor_log_meta.hpp"
#include "sysid/import_notes.hpp"
#include "sysid/log_units.hpp"
#include "tern/math.hpp"

namespace tern::core::sysid {

namespace {

constexpr double kMaxGap = 1.0;  ///< s: the estimate is not interpolated across a longer gap

/// s: the longest step of the series' time base before decimation. A command is in force from the
/// first time-base sample at or after its stamp plus its delay, so a coarser base rounds every
/// command's timing up to its step: on an IMU logged at 50 Hz the output error then fitted the
/// aileron's delay 10 ms long and C_ell_p and C_ell_delta_a came out 40 % large (a rolling moment
/// whose damping and control power trade with the delay in closed loop); interpolated onto a 5-ms
/// base they came out within 2 % (the bench's seed 3). 5 ms: 7 deg of phase at the band's 4 Hz.
constexpr double kMaxBaseStep = 0.005;

/// s: commands logged at most this far apart are each held until the next row (a controller's every
/// output: ROSplane 100 Hz, PX4 250 Hz, ArduPlane 50-400 Hz); rows further apart are samples of a
/// faster controller's output (ArduPilot's RCOU at 10-25 Hz), joined linearly: held, they would
/// lag by half their interval. On the bench's seed 3 at 10 Hz, held, the output error fitted the
/// commands acting 25-35 ms before their stamps and C_ell_p came out 12-34 % large; joined, 1-6 %.
/// Over seeds 1-5 the roll's worst seed at 10 Hz stays some 35 % off (seed 1: 6 -> 37 %, seeds 3
/// and 4: 34 -> 1 % and 32 -> 16 %, the IMU at 50 Hz): a 10-Hz record keeps little of a 3-Hz
/// multisine.
constexpr double kMaxHeldInterval = 0.03;

using Column = std::vector<double>;

CsvTable read_table(const std::filesystem::path& file, const std::vector<std::string>& wanted, const char* why) {
  if (!std::filesystem::exists(file)) throw ConfigError(fmt::format("{}: no such table: {}", file.string(), why));
  CsvTable table = read_csv_table(file, wanted);
  for (const auto& name : wanted)
    if (!table.has(name)) throw ConfigError(fmt::format("{}: no column '{}'", file.string(), name));
  return table;
}

/// An angle made continuous (no jump of 2 pi between neighbours).
Column unwrapped(const Column& a) {
  Column out(a);
  for (std::size_t k = 1; k < out.size(); ++k) out[k] = out[k - 1] + wrap_pi(a[k] - a[k - 1]);
  return out;
}

/// The IMU rows whose every value is finite, in time order (rows going backwards dropped).
std::vector<std::size_t> usable_imu_rows(const CsvTable& imu, const std::vector<std::string>& names) {
  std::vector<std::size_t> rows;
  const Column& t = imu.at("t");
  for (std::size_t k = 0; k < imu.rows; ++k) {
    bool finite = std::isfinite(t[k]) && (rows.empty() || t[k] > t[rows.back()]);
    for (const auto& n : names) finite = finite && std::isfinite(imu.at(n)[k]);
    if (finite) rows.push_back(k);
  }
  return rows;
}

/// Commands in force at each time of `tq` (the last row at or before it; before the first row,
/// the first; a row that is not a number leaves the one before it in force; `joined`: between two
/// rows, the line joining them), through a first-order lag of time constant tau (0: none). The lag
/// is solved exactly from each row's own instant (a step's or a ramp's response), not from the
/// sample of tq after it: a command acts from its stamp plus its delay, wherever that falls
/// between two samples.
Column commands_in_force(const Column& t_cmd, const Column& cmd, const Column& tq, double tau, bool joined = false) {
  Column out(tq.size());
  if (tq.empty()) return out;
  const auto first = std::find_if(cmd.begin(), cmd.end(), [](double v) { return std::isfinite(v); });
  double u = first == cmd.end() ? 0.0 : *first;  // a row that is not a number leaves the one before in force
  std::size_t j = 0;                             // the row in force from t_cmd[j] on
  auto input = [&](double t) {                   // the command at t, row j in force
    const bool line = joined && j + 1 < t_cmd.size() && t >= t_cmd[j] && std::isfinite(cmd[j]) && std::isfinite(cmd[j + 1]);
    return line ? cmd[j] + (t - t_cmd[j]) / (t_cmd[j + 1] - t_cmd[j]) * (cmd[j + 1] - cmd[j]) : u;
  };
  double s = t_cmd.empty() ? tq.front() : std::min(tq.front(), t_cmd.front());
  double y = u;
  auto advance = [&](double e) {  // y from s to e, the input a line between them: exact
    if (!(e > s) || tau <= 0.0) return void(s = std::max(s, e));
    const double u_s = input(s), u_e = input(e), b = (u_e - u_s) / (e - s);
    y = u_e - b * tau + (y - u_s + b * tau) * std::exp(-(e - s) / tau);
    s = e;
  };
  for (std::size_t k = 0; k < tq.size(); ++k) {
    if (!t_cmd.empty() && s < t_cmd.front() && t_cmd.front() < tq[k]) advance(t_cmd.front());  // the first row's line starts there
    while (j + 1 < t_cmd.size() && t_cmd[j + 1] <= tq[k]) {
      advance(t_cmd[j + 1]);
      ++j;
      if (std::isfinite(cmd[j])) u = cmd[j];
    }
    advance(tq[k]);
    out[k] = tau > 0.0 ? y : input(tq[k]);
  }
  return out;
}

/// At each time of `tq`, whether the command (or pressure) in force there (commands_in_force) is more than
/// kMaxGap older than it: the last row that is a number lies further back (a run of rows that are
/// not numbers, the table's own gap, its end). Before the first row, not stale (the first row held
/// back, as commands_in_force does).
std::vector<unsigned char> stale_commands(const Column& t_cmd, const Column& cmd, const Column& tq) {
  std::vector<unsigned char> out(tq.size(), 0);
  double last = -std::numeric_limits<double>::infinity();
  bool started = false;
  std::size_t j = 0;
  for (std::size_t k = 0; k < tq.size(); ++k) {
    while (j < t_cmd.size() && t_cmd[j] <= tq[k]) {
      started = true;
      if (std::isfinite(cmd[j])) last = t_cmd[j];
      ++j;
    }
    out[k] = started && !(tq[k] - last <= kMaxGap) ? 1 : 0;
  }
  return out;
}

/// Linear interpolation of (ts, v) at each time of tq; NaN outside or across a gap > kMaxGap.
Column interpolated(const Column& ts, const Column& v, const Column& tq) {
  Column out(tq.size(), std::nan(""));
  std::size_t j = 0;
  for (std::size_t k = 0; k < tq.size(); ++k) {
    while (j + 1 < ts.size() && ts[j + 1] < tq[k]) ++j;
    if (j + 1 >= ts.size() || ts[j] > tq[k] || ts[j + 1] - ts[j] > kMaxGap) continue;
    const double f = (tq[k] - ts[j]) / (ts[j + 1] - ts[j]);
    out[k] = v[j] + f * (v[j + 1] - v[j]);
  }
  return out;
}

double median_interval(const Column& t) {
  Column d;
  for (std::size_t k = 1; k < t.size(); ++k) d.push_back(t[k] - t[k - 1]);
  return median(std::move(d));
}

/// Whether a command table's rows are a slower controller's record, to be joined by lines rather
/// than held (kMaxHeldInterval).
bool joined_rows(const CsvTable& table) { return table.rows > 2 && median_interval(table.at("t")) > kMaxHeldInterval; }

Column central_difference(const Column& x, const Column& t) {
  Column out(x.size(), 0.0);
  for (std::size_t k = 1; k + 1 < x.size(); ++k) out[k] = (x[k + 1] - x[k - 1]) / (t[k + 1] - t[k - 1]);
  if (x.size() > 2) {
    out.front() = out[1];
    out.back() = out[x.size() - 2];
  }
  return out;
}

/// One note when `column` of `table` has rows that are not numbers (commands_in_force holds the row
/// before each).
void note_not_numbers(const CsvTable& table, const char* column, std::vector<std::string>& notes) {
  const Column& c = table.at(column);
  const auto bad = std::count_if(c.begin(), c.end(), [](double v) { return !std::isfinite(v); });
  if (bad > 0)
    notes.push_back(
        fmt::format("{}: {} of {} rows' {} not a number: the row before each held", table.file.string(), bad, c.size(), column));
}

/// Throws ConfigError when `column` of the actuators' table has rows and none is a number (a
/// surface's channel never logged): the identification would take it as a surface that never
/// moved and fit the moments without it. A table without rows (a flight that ended before its
/// controllers ran) is left to the checks of the estimate's validity and of the excitation. A value
/// outside its unit's range is refused too (log_units.hpp).
void require_commands(const CsvTable& table, const char* column) {
  const Column& c = table.at(column);
  if (!c.empty() && std::none_of(c.begin(), c.end(), [](double v) { return std::isfinite(v); }))
    throw ConfigError(
        fmt::format("{}: {} is a number in none of its {} rows: the surfaces' commands are required (log 0 for a "
                    "surface the aircraft does not have; docs/sensor-log.md, actuators)",
                    table.file.string(), column, c.size()));
  require_command_unit(table, column);
}

/// Each column (the time `t` among them) with n - 1 samples interpolated linearly into every
/// interval, n the least for which the median interval / n is at most kMaxBaseStep (5 % spared, for
/// a clock's jitter): the logged samples kept, a gap stretched as before. n = 1 (the columns as
/// they are) at 190 Hz or faster, and for rows more than kMaxGap apart. Returns n.
std::size_t interpolate_to_base(std::map<std::string, Column>& cols) {
  const double logged = median_interval(cols.at("t"));
  if (!(logged > kMaxBaseStep && logged <= kMaxGap)) return 1;  // NaN, or rows too far apart to be a flight's IMU
  const auto n = static_cast<std::size_t>(std::ceil(logged / kMaxBaseStep - 0.05));
  if (n <= 1) return 1;
  for (auto& [name, c] : cols) {
    Column fine;
    fine.reserve((c.size() - 1) * n + 1);
    for (std::size_t k = 0; k + 1 < c.size(); ++k)
      for (std::size_t j = 0; j < n; ++j) fine.push_back(c[k] + static_cast<double>(j) / static_cast<double>(n) * (c[k + 1] - c[k]));
    fine.push_back(c.back());
    c = std::move(fine);
  }
  return n;
}

/// `table` without the rows whose time is not a number or earlier than the row before (counted
/// in one note): a stamp that is not a number would otherwise hold every later row back.
CsvTable in_time_order(const CsvTable& table, std::vector<std::string>& notes) {
  const Column& t = table.at("t");
  std::vector<std::size_t> keep;
  for (std::size_t k = 0; k < table.rows; ++k)
    if (std::isfinite(t[k]) && (keep.empty() || t[k] >= t[keep.back()])) keep.push_back(k);
  if (keep.size() == table.rows) return table;
  CsvTable out = table;
  for (auto& [name, column] : out.columns) {
    Column c;
    c.reserve(keep.size());
    for (const std::size_t k : keep) c.push_back(column[k]);
    column = std::move(c);
  }
  out.rows = keep.size();
  notes.push_back(fmt::format("{}: {} of {} rows whose time is not a number or goes back: dropped", table.file.string(),
                              table.rows - keep.size(), table.rows));
  return out;
}

/// Every `step`-th element.
Column decimated(const Column& x, std::size_t step) {
  Column out;
  out.reserve(x.size() / step + 1);
  for (std::size_t k = 0; k < x.size(); k += step) out.push_back(x[k]);
  return out;
}

}  // namespace

void check_sensor_log(const std::filesystem::path& log_dir, bool replayed) {
  std::vector<std::pair<const char*, const char*>> tables = {
      {"imu.csv", "the IMU's specific force and rates are required"},
      {"actuators.csv", "the surfaces' commands are required (docs/sensor-log.md, actuators)"}};
  if (replayed)
    tables.emplace_back("gnss.csv",
                        "tern's estimator initialises on GNSS (docs/sensor-log.md); or give --estimate RUN, a run whose topics/state.csv "
                        "holds another estimate");
  for (const auto& [name, why] : tables) {
    const std::filesystem::path file = log_dir / "topics" / name;
    if (!std::filesystem::exists(file))
      throw ConfigError(fmt::format("{}: no such table: {}{}", file.string(), why, import_said(log_dir / "sensor_log.yaml", name)));
  }
}

namespace {
Eigen::Vector3d installation(const std::filesystem::path& estimate, const std::string& name) {
  const std::filesystem::path file = estimate / "params.csv";
  if (!std::filesystem::exists(file)) return Eigen::Vector3d::Zero();
  for (const auto& [key, values] : read_params_csv(file).values) {
    if (key.size() <= name.size() || key.compare(key.size() - name.size() - 1, std::string::npos, "." + name) != 0) continue;
    const YAML::Node v = YAML::Load(values.back().second);
    if (!v.IsSequence() || v.size() != 3)
      throw ConfigError(fmt::format("{}: {}: '{}' is not a 3-vector", file.string(), key, values.back().second));
    return {v[0].as<double>(), v[1].as<double>(), v[2].as<double>()};
  }
  return Eigen::Vector3d::Zero();
}
}  // namespace

void read_installation(const std::filesystem::path& estimate_dir, FlightSeriesOptions& o) {
  o.imu_position = installation(estimate_dir, "imu_position");
  o.imu_mount = installation(estimate_dir, "imu_mount");
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

std::vector<double> zero_phase_lowpass(const std::vector<double>& x, double cutoff_hz, double dt_s) {
  if (x.size() < 3 || cutoff_hz <= 0.0) return x;
  // Bilinear transform with pre-warping of the analogue Butterworth s^2 + sqrt(2) s + 1.
  const double K = std::tan(kPi * std::min(cutoff_hz * dt_s, 0.45));
  const double norm = 1.0 / (1.0 + std::sqrt(2.0) * K + K * K);
  const double b0 = K * K * norm, b1 = 2.0 * b0, b2 = b0;
  const double a1 = 2.0 * (K * K - 1.0) * norm, a2 = (1.0 - std::sqrt(2.0) * K + K * K) * norm;
  auto pass = [&](std::vector<double>& v) {
    double x1 = v.front(), x2 = v.front(), y1 = v.front(), y2 = v.front();
    for (double& s : v) {
      const double y = b0 * s + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2;
      x2 = x1, x1 = s, y2 = y1, y1 = y;
      s = y;
    }
  };
  std::vector<double> y(x);
  pass(y);
  std::reverse(y.begin(), y.end());
  pass(y);
  std::reverse(y.begin(), y.end());
  return y;
}

/// alpha and beta of the ground velocity less the steady wind (header), at every sample.
void flow_angles_from_steady_wind(FlightSeries& s) {
  s.alpha.assign(s.size(), std::nan("")), s.beta.assign(s.size(), std::nan(""));
  for (std::size_t k = 0; k < s.size(); ++k) {
    const Eigen::Matrix3d R_nb = rotation_from_euler(s.phi[k], s.theta[k], s.psi[k]);  // body to NED
    const Eigen::Vector3d v_r = Eigen::Vector3d(s.u[k], s.v[k], s.w[k]) - R_nb.transpose() * Eigen::Vector3d(s.w_n[k], s.w_e[k], s.w_d[k]);
    if (!v_r.allFinite() || !(v_r.norm() > 0.0)) continue;
    s.alpha[k] = std::atan2(v_r.z(), v_r.x());
    s.beta[k] = std::asin(v_r.y() / v_r.norm());
  }
}

namespace {

/// log_units.hpp's checks that need neither the estimate nor the IMU's mounting (a rotation keeps
/// every magnitude) on the log's own tables, so that a log in another unit is one line before it
/// is replayed, not after the replay's warnings (gyros in deg/s: 629 of them).
void require_units_before_replay(const FlightTables& f) {
  for (const char* c : kCommandColumns) require_commands(f.actuators, c);
  const std::vector<std::string> names(kImuColumns.begin(), kImuColumns.end());
  const std::vector<std::size_t> rows = usable_imu_rows(f.imu, names);
  std::map<std::string, Column> usable;
  for (const auto& n : names) {
    Column& c = usable[n];
    c.reserve(rows.size());
    for (const std::size_t k : rows) c.push_back(f.imu.at(n)[k]);
  }
  require_imu_magnitudes(f.imu, usable);
}

std::vector<std::string> with_t(const auto& names) {
  std::vector<std::string> v{"t"};
  v.insert(v.end(), names.begin(), names.end());
  return v;
}

}  // namespace

FlightTables read_log_tables(const std::filesystem::path& log_dir) {
  FlightTables f;
  f.imu = read_table(log_dir / "topics" / "imu.csv", with_t(kImuColumns), "the IMU's specific force and rates are required");
  f.actuators = read_table(log_dir / "topics" / "actuators.csv", with_t(kCommandColumns),
                           "the surfaces' commands are required (docs/sensor-log.md, actuators)");
  const std::filesystem::path excitation = log_dir / "topics" / "excitation.csv";
  if (std::filesystem::exists(excitation)) f.excitation = read_table(excitation, with_t(kCommandColumns), "");
  const std::filesystem::path pitot = log_dir / "topics" / "diff_pressure.csv";
  if (std::filesystem::exists(pitot)) f.diff_pressure = read_table(pitot, {"t", "pressure"}, "");
  const std::filesystem::path meta = log_dir / "sensor_log.yaml";
  if (const auto w = read_airborne_window(meta)) f.declared_airborne = DeclaredAirborne{w->start_s, w->end_s, meta.string()};
  require_units_before_replay(f);
  return f;
}

void read_estimate_table(FlightTables& tables, const std::filesystem::path& estimate_dir) {
  tables.state = read_table(estimate_dir / "topics" / "state.csv", with_t(kStateColumns), "the estimate (tern replay LOG) is required");
}

std::vector<double> throttle_in_force(const FlightTables& tables, const std::vector<double>& t, double tau) {
  std::vector<std::string> notes;
  const CsvTable act = in_time_order(tables.actuators, notes);
  require_commands(act, "delta_t");
  const bool joined = joined_rows(act);
  return commands_in_force(act.at("t"), act.at("delta_t"), t, tau, joined);
}

FlightSeries series_from_tables(const FlightTables& f, const FlightSeriesOptions& o) {
  const CsvTable &imu = f.imu, &st = f.state;
  std::vector<std::string> notes;
  const CsvTable act = in_time_order(f.actuators, notes);
  const std::vector<std::string> imu_names(kImuColumns.begin(), kImuColumns.end());
  const std::vector<std::size_t> rows = usable_imu_rows(imu, imu_names);
  if (rows.size() < 3) throw ConfigError(fmt::format("{}: fewer than 3 usable IMU rows", imu.file.string()));
  // the IMU's axes turned into the body's (the estimator's imu_mount)
  const Eigen::Matrix3d R_bi = rotation_from_euler(o.imu_mount.x(), o.imu_mount.y(), o.imu_mount.z());
  std::map<std::string, Column> body;
  for (const char* sensor : {"accel", "gyro"}) {
    const std::string x = std::string(sensor) + "_x", y = std::string(sensor) + "_y", z = std::string(sensor) + "_z";
    for (const auto& n : {x, y, z}) body[n].resize(rows.size());
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const Eigen::Vector3d v = R_bi * Eigen::Vector3d(imu.at(x)[rows[k]], imu.at(y)[rows[k]], imu.at(z)[rows[k]]);
      body[x][k] = v.x(), body[y][k] = v.y(), body[z][k] = v.z();
    }
  }
  body["t"].resize(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) body["t"][k] = imu.at("t")[rows[k]];
  require_imu_units(imu, body);
  const double logged_dt = median_interval(body.at("t"));
  const std::size_t n = interpolate_to_base(body);
  auto pick = [&](const std::string& name) { return body.at(name); };
  FlightSeries s;
  s.notes = std::move(notes);
  if (n > 1)
    s.notes.push_back(
        fmt::format("{}: logged every {:.1f} ms, interpolated linearly onto a {:.1f}-ms base: a command's timing is not "
                    "rounded to the IMU's interval",
                    imu.file.string(), 1e3 * logged_dt, 1e3 * logged_dt / static_cast<double>(n)));
  const Column t = pick("t");
  const double dt = median_interval(t);
  if (!(dt > 0.0)) throw ConfigError(fmt::format("{}: the IMU's rows share one time", imu.file.string()));
  auto est = [&](const std::string& name, bool angle = false) {
    return interpolated(st.at("t"), angle ? unwrapped(st.at(name)) : st.at(name), t);
  };
  const Column valid = est("valid");
  auto lp = [&](const Column& c) { return zero_phase_lowpass(c, o.filter_hz, dt); };
  // the gyro less the estimated bias (zero where the estimate is not valid)
  auto rate = [&](const char* gyro, const char* bias) {
    Column g = pick(gyro);
    const Column b = est(bias);
    for (std::size_t k = 0; k < g.size(); ++k) g[k] -= std::isfinite(b[k]) ? b[k] : 0.0;
    return lp(g);
  };
  const Column p = rate("gyro_x", "b_x"), q = rate("gyro_y", "b_y"), r = rate("gyro_z", "b_z");
  const std::size_t step = o.rate_hz > 0.0 ? std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(1.0 / (dt * o.rate_hz)))) : 1;
  auto keep = [&](const Column& c) { return decimated(c, step); };
  // a command that acts `delay` after its stamp is in force from its stamp plus the delay
  auto delayed = [](Column t_cmd, double delay) {
    for (double& v : t_cmd) v += delay;
    return t_cmd;
  };
  const bool joined = joined_rows(act);
  if (joined)
    s.notes.push_back(
        fmt::format("{}: commands logged every {:.0f} ms: a record of a faster controller's output, its rows joined "
                    "linearly (held, they would lag by half that)",
                    act.file.string(), 1e3 * median_interval(act.at("t"))));
  std::vector<unsigned char> stale(t.size(), 0);  // a command held more than kMaxGap: its samples not valid
  auto command = [&](const char* name, double delay, double tau) {
    require_commands(act, name);
    note_not_numbers(act, name, s.notes);
    const Column t_cmd = delayed(act.at("t"), delay);
    const std::vector<unsigned char> old = stale_commands(t_cmd, act.at(name), t);
    for (std::size_t k = 0; k < t.size(); ++k) stale[k] = stale[k] || old[k];
    return keep(lp(commands_in_force(t_cmd, act.at(name), t, tau, joined)));
  };
  s.t = keep(t);
  const Column p_dot = central_difference(p, t), q_dot = central_difference(q, t), r_dot = central_difference(r, t);
  Column ax = lp(pick("accel_x")), ay = lp(pick("accel_y")), az = lp(pick("accel_z"));
  for (std::size_t k = 0; k < t.size(); ++k) {  // to the CG: a - w' x r - w x (w x r)
    const Eigen::Vector3d w(p[k], q[k], r[k]), wd(p_dot[k], q_dot[k], r_dot[k]);
    const Eigen::Vector3d a = Eigen::Vector3d(ax[k], ay[k], az[k]) - wd.cross(o.imu_position) - w.cross(w.cross(o.imu_position));
    ax[k] = a.x(), ay[k] = a.y(), az[k] = a.z();
  }
  s.a_x = keep(ax), s.a_y = keep(ay), s.a_z = keep(az);
  s.p_dot = keep(p_dot), s.q_dot = keep(q_dot), s.r_dot = keep(r_dot);
  s.p = keep(p), s.q = keep(q), s.r = keep(r);
  const auto& d = o.command_delay_s;
  s.delta_a = command("delta_a", d[0], o.servo_tau), s.delta_e = command("delta_e", d[1], o.servo_tau);
  s.delta_r = command("delta_r", d[2], o.servo_tau);
  s.delta_t = command("delta_t", 0.0, o.motor_tau.value_or(o.servo_tau));
  if (f.excitation) {
    const CsvTable ex = in_time_order(*f.excitation, s.notes);
    const bool ex_joined = joined_rows(ex);
    auto part = [&](const char* name, double delay, double tau) {
      note_not_numbers(ex, name, s.notes);
      return keep(lp(commands_in_force(delayed(ex.at("t"), delay), ex.at(name), t, tau, ex_joined)));
    };
    s.exc_delta_a = part("delta_a", d[0], o.servo_tau), s.exc_delta_e = part("delta_e", d[1], o.servo_tau);
    s.exc_delta_r = part("delta_r", d[2], o.servo_tau), s.exc_delta_t = part("delta_t", 0.0, o.motor_tau.value_or(o.servo_tau));
  }
  // the estimate: interpolated, then filtered alike; where it is NaN (before the first row, across
  // a gap) the filter sees the nearest value and the result stays NaN
  auto filtered = [&](const std::string& name, bool angle, double cutoff_hz) {
    Column c = est(name, angle);
    Column filled = c;
    for (std::size_t k = 1; k < filled.size(); ++k)
      if (!std::isfinite(filled[k])) filled[k] = filled[k - 1];
    for (std::size_t k = filled.size() - 1; k-- > 0;)
      if (!std::isfinite(filled[k])) filled[k] = filled[k + 1];
    Column f = std::isfinite(filled.front()) ? zero_phase_lowpass(filled, cutoff_hz, dt) : filled;
    for (std::size_t k = 0; k < f.size(); ++k)
      if (!std::isfinite(c[k])) f[k] = c[k];
    return keep(f);
  };
  auto estimate = [&](const std::string& name, bool angle = false) { return filtered(name, angle, o.filter_hz); };
  s.Va = estimate("Va");
  s.phi = estimate("phi", true), s.theta = estimate("theta"), s.psi = estimate("psi", true);
  s.p_n = estimate("p_n"), s.p_e = estimate("p_e"), s.p_d = estimate("p_d");
  s.u = estimate("u"), s.v = estimate("v"), s.w = estimate("w");
  const double wind_hz = o.steady_wind_s > 0.0 ? 1.0 / o.steady_wind_s : o.filter_hz;
  // the steady wind is horizontal: the estimator's vertical wind, without its lift update, is its
  // process noise's random wander (0.76 m/s RMS on the bench's seed 1: 1.7 deg of alpha at 25 m/s)
  s.w_n = filtered("w_n", false, wind_hz), s.w_e = filtered("w_e", false, wind_hz);
  s.w_d.assign(s.t.size(), 0.0);
  flow_angles_from_steady_wind(s);
  s.qbar = Column(s.t.size(), std::nan(""));
  if (f.diff_pressure) {
    const CsvTable dp = in_time_order(*f.diff_pressure, s.notes);
    note_not_numbers(dp, "pressure", s.notes);
    // a pressure last logged more than kMaxGap before is not held: those samples are left out (the
    // estimator's airspeed there, beside the scaled pitot's elsewhere, bent the pitching moment)
    const Column q = lp(commands_in_force(dp.at("t"), dp.at("pressure"), t, 0.0));
    const std::vector<unsigned char> old = stale_commands(dp.at("t"), dp.at("pressure"), t);
    for (std::size_t k = 0; k < t.size(); ++k) stale[k] = stale[k] || old[k];
    s.qbar = keep(q);
  }
  Column v = valid;
  std::size_t held = 0;
  for (std::size_t k = 0; k < v.size(); ++k)
    if (stale[k] && std::isfinite(v[k]) && v[k] > 0.5) v[k] = 0.0, ++held;
  if (held > 0)
    s.notes.push_back(
        fmt::format("{:.1f} s of the estimate's valid samples left out: a command (actuators.csv) or the pitot's pressure "
                    "(diff_pressure.csv) there last logged more than {:g} s before (rows that are not numbers, or none)",
                    static_cast<double>(held) * dt, kMaxGap));
  v = keep(v);
  s.valid.resize(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) s.valid[k] = std::isfinite(v[k]) && v[k] > 0.5 ? 1 : 0;
  s.declared_airborne = f.declared_airborne;
  return s;
}

}  // namespace tern::core::sysid
