// The replay report's physics check of the attitude (replay_report.hpp, SpecificForceCheck): the
// accelerometer's specific force against R^T (a - g) with a from the GNSS velocity and the yaw
// solved for at each epoch, for the estimate's roll and pitch and for the reference's.
#include <cmath>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "replay/replay_report_parts.hpp"
#include "tern/math.hpp"

namespace tern::core::replay_report {

namespace {

constexpr std::size_t kMinFixes = 4;    ///< fixes within the span for a velocity slope
constexpr std::size_t kMinImu = 4;      ///< accelerometer samples within the span
constexpr double kMinCheckSpeed = 5.0;  ///< m/s of GNSS horizontal speed: in flight
/// m/s^2: a tilt axis is judged only where the GNSS acceleration along it (roll: along the track,
/// pitch: across it) is at most this; beyond, a yaw turned by about g * tilt / that acceleration
/// explains the tilt instead (at this bound a tilt error delta is still seen as at least
/// 1 - kFreeYawAxis / sqrt(kFreeYawAxis^2 + (g delta)^2) of it: 37 % of 3.6 deg, 61 % of 7 deg).
constexpr double kFreeYawAxis = 0.5;

/// Slope of y over x by least squares (x centred on x0); NaN with fewer than two distinct x.
double slope(const std::vector<double>& x, const std::vector<double>& y, double x0) {
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  const double n = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double u = x[i] - x0;
    sx += u, sy += y[i], sxx += u * u, sxy += u * y[i];
  }
  const double d = n * sxx - sx * sx;
  return d > 1e-12 ? (n * sxy - sx * sy) / d : NAN;
}

/// The GNSS's acceleration at an epoch (NED, m/s^2), and its horizontal part along and across the
/// track (the fixes' mean horizontal velocity): the axes the per-axis rule reads.
struct GnssAcceleration {
  Eigen::Vector3d a;
  double along = 0.0, across = 0.0;
};

/// The GNSS acceleration at t from the fixes within the span, or nullopt.
std::optional<GnssAcceleration> gnss_acceleration(const CsvTable& g, const FixTimes& times, double t) {
  std::vector<double> x, vn, ve, vd;
  const auto &fix = g.at("fix_type"), &n = g.at("vel_n"), &e = g.at("vel_e"), &d = g.at("vel_d");
  double speed = 0.0;
  Eigen::Vector2d v = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < g.rows; ++k) {
    if (std::fabs(times.tov[k] - t) > kSpecificForceSpan || !(fix[k] >= 3.0) || !std::isfinite(n[k] + e[k] + d[k])) continue;
    x.push_back(times.tov[k]), vn.push_back(n[k]), ve.push_back(e[k]), vd.push_back(d[k]);
    speed = std::max(speed, std::hypot(n[k], e[k]));
    v += Eigen::Vector2d(n[k], e[k]);
  }
  if (x.size() < kMinFixes || speed < kMinCheckSpeed || v.norm() == 0.0) return std::nullopt;
  const Eigen::Vector3d a(slope(x, vn, t), slope(x, ve, t), slope(x, vd, t));
  const Eigen::Vector2d track = v.normalized();
  if (!a.allFinite()) return std::nullopt;
  return GnssAcceleration{a, a.head<2>().dot(track), track.x() * a.y() - track.y() * a.x()};
}

/// The accelerometer's mean specific force (m/s^2, its own axes) within the span about t.
std::optional<Eigen::Vector3d> mean_specific_force(const CsvTable& imu, double t) {
  const auto [first, last] = index_range(imu.at("time"), t - kSpecificForceSpan, t + kSpecificForceSpan);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::size_t n = 0;
  for (std::size_t k = first; k < last; ++k) {
    const Eigen::Vector3d f(imu.at("accel_x")[k], imu.at("accel_y")[k], imu.at("accel_z")[k]);
    if (f.allFinite()) sum += f, ++n;
  }
  return n >= kMinImu ? std::optional<Eigen::Vector3d>(sum / static_cast<double>(n)) : std::nullopt;
}

/// An attitude's roll and pitch (rad): all the check reads of it (no yaw).
struct Tilt {
  double phi = 0.0, theta = 0.0;
};

/// The state's roll and pitch at t, or nullopt (no bracket, not valid on both sides, NaN).
std::optional<Tilt> state_tilt(const CsvTable& s, double t) {
  const auto b = bracket(s.at("time"), t, kMaxGap);
  if (!b || !(s.at("valid")[b->k] > 0.5 && s.at("valid")[b->f == 0.0 ? b->k : b->k + 1] > 0.5)) return std::nullopt;
  const Tilt e{lerp(s.at("phi"), *b, true), lerp(s.at("theta"), *b, true)};
  return std::isfinite(e.phi + e.theta) ? std::optional(e) : std::nullopt;
}

/// The reference's roll and pitch, each between its own samples.
struct ReferenceTilt {
  Series phi, theta;
  explicit ReferenceTilt(const CsvTable& r) : phi(r, "phi"), theta(r, "theta") {}
  std::optional<Tilt> at(double t) const {
    const Tilt e{interpolate(phi.t, phi.v, t, kMaxGap, true), interpolate(theta.t, theta.v, t, kMaxGap, true)};
    return std::isfinite(e.phi + e.theta) ? std::optional(e) : std::nullopt;
  }
};

/// What an attitude's roll and pitch leave of the specific force f_ned = a - g with the yaw that
/// fits best (replay_report.hpp, SpecificForceCheck), body axes, m/s^2: the level frame's
/// f_lev = Ry(theta) Rx(phi) f_body against Rz(psi)^T f_ned, whose vertical part is the same for
/// every psi and whose horizontal part is any vector of length h = |f_ned horizontal|, the nearest
/// one along f_lev's own horizontal part (along x when f_lev has none).
Eigen::Vector3d yaw_free_residual(double phi, double theta, const Eigen::Vector3d& f_ned, const Eigen::Vector3d& f) {
  const Eigen::Matrix3d L =
      (Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitX())).toRotationMatrix();
  const Eigen::Vector3d f_lev = L * f;  // body FRD -> level (heading) frame
  const double h = f_ned.head<2>().norm(), p = f_lev.head<2>().norm();
  const Eigen::Vector2d u = p > 0.0 ? Eigen::Vector2d(f_lev.head<2>() / p) : Eigen::Vector2d::UnitX();
  return L.transpose() * Eigen::Vector3d((p - h) * u.x(), (p - h) * u.y(), f_lev.z() - f_ned.z());
}

/// Adds the implied pitch and roll errors (deg) of an attitude's roll and pitch at one
/// epoch: pitch where the GNSS acceleration across the track is at most kFreeYawAxis, roll where
/// the one along it is (else the free yaw absorbs that tilt).
void add_epoch(const Tilt& tilt, const GnssAcceleration& g, const Eigen::Vector3d& f, ErrorSum& pitch, ErrorSum& roll) {
  const Eigen::Vector3d f_ned = g.a - Eigen::Vector3d(0.0, 0.0, kStandardGravity);
  const Eigen::Vector3d res = yaw_free_residual(tilt.phi, tilt.theta, f_ned, f);
  if (std::fabs(g.across) <= kFreeYawAxis) pitch.add(-res.x() / f_ned.norm() * kDegPerRad);  // a tilt delta moves f by |f| delta
  if (std::fabs(g.along) <= kFreeYawAxis) roll.add(res.y() / f_ned.norm() * kDegPerRad);
}

}  // namespace

SpecificForceCheck check_specific_force(const RunTables& run, const EstimatorCounters& c, const ReplayWindow& w) {
  SpecificForceCheck out;
  if (!run.imu || !run.imu->has("accel_x")) out.absent = "absent (no accelerometer in topics/imu.csv)";
  if (!run.gnss) out.absent = "absent (no topics/gnss.csv)";
  if (!out.absent.empty()) return out;
  const FixTimes times = fix_times(run, c, w);
  const bool ref = run.reference && run.reference->has("phi") && run.reference->has("theta");
  const std::optional<ReferenceTilt> reference = ref ? std::optional<ReferenceTilt>(*run.reference) : std::nullopt;
  ErrorSum pitch, roll, ref_pitch, ref_roll;
  for (double t = w.start_s + kSpecificForceSpan; t <= w.end_s - kSpecificForceSpan; t += kSpecificForceStep) {
    const auto a = gnss_acceleration(*run.gnss, times, t);
    const auto f = a ? mean_specific_force(*run.imu, t) : std::nullopt;
    const auto est = f ? state_tilt(run.state, t) : std::nullopt;
    if (!est) continue;
    ++out.epochs;
    if (a->a.head<2>().norm() > kFreeYawAxis) ++out.accelerated;
    add_epoch(*est, *a, *f, pitch, roll);
    if (const auto r = reference ? reference->at(t) : std::nullopt) add_epoch(*r, *a, *f, ref_pitch, ref_roll);
  }
  const std::string mount =
      run.params.values.count(c.instance + ".imu_mount") ? run.params.values.at(c.instance + ".imu_mount").front().second : "unknown";
  out.rule = fmt::format(
      "every {} s of the window where the GNSS (>= {} fixes with fix_type >= 3 within +-{} s at their time of validity, "
      "{} m/s or faster) gives the acceleration a by a straight-line fit of its velocity and the accelerometer (imu.csv, its own "
      "axes; imu_mount {} not applied) its mean f over the same span: res = f - R(phi, theta, psi*)^T (a - g), g = {} m/s^2, with "
      "the attitude's roll and pitch (interpolated at the epoch; the state where valid) and the yaw psi* that fits best (no "
      "estimator's yaw); pitch error -res_x / |a - g| where the GNSS acceleration across the track (the fixes' mean horizontal "
      "velocity) is <= {} m/s^2, roll error res_y / |a - g| where the one along it is: the same epochs for every attitude",
      kSpecificForceStep, kMinFixes, kSpecificForceSpan, kMinCheckSpeed, mount, kStandardGravity, kFreeYawAxis);
  out.pitch = pitch.figure("deg", out.rule);
  out.roll = roll.figure("deg", out.rule);
  out.reference_pitch = ref_pitch.figure("deg", ref ? out.rule : "no reference attitude");
  out.reference_roll = ref_roll.figure("deg", ref ? out.rule : "no reference attitude");
  return out;
}

}  // namespace tern::core::replay_report
