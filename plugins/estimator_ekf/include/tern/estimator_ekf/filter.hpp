// tern/estimator_ekf/filter.hpp: the error-state (multiplicative) extended Kalman filter core.
//
// Plain C++ and Eigen: no tern host or plugin types. All matrices are fixed size; propagate() and
// update() never allocate.
//
// Nominal state x (NominalState):
//   p      NED position relative to the origin, m
//   v      NED ground velocity, m/s
//   q      attitude, unit quaternion rotating body FRD vectors into NED (v_ned = q * v_body)
//   b_g    gyro bias, body FRD, rad/s          (gyro = omega + b_g + noise)
//   b_a    accelerometer bias, body FRD, m/s^2 (accel = f + b_a + noise, f = specific force)
//   wind   horizontal wind (w_n, w_e), m/s (the vertical wind is w_d below)
//   b_baro barometric-altitude bias, m         (baro altitude = -p_d + b_baro + noise)
//   e_gnss GNSS position error, NED, m          (GNSS position = p + e_gnss + noise)
//   S_g    gyro sensitivity error, 3x3         (omega = (I - S_g) (w_m - b_g): the scale-factor
//          errors on the diagonal, cross-axis sensitivity and the board's mounting rotation off
//          it; what the FCU's boot calibration cannot see, since it calibrates at rest)
//   b_m    magnetometer offset, body FRD, fraction of the Earth's field intensity (field =
//          field_strength (R^T m_n + b_m) + noise): residual hard iron, the motor current's field
//   k_sp   static-pressure error coefficient: the static port reads p + k_sp q_bar (q_bar the
//          dynamic pressure), the installation's position error (PX4 EKF2's EKF2_PCOEF_*)
//   w_d    vertical wind (down), m/s: the vertical gust, seen through the lift (NormalForce)
//
// Error state dx (35 components, index constants in namespace idx):
//   dp(3) dv(3) dtheta(3) db_g(3) db_a(3) dw(2) db_baro(1) de_gnss(3) dS_g(9, row by row) db_m(3)
//   dk_sp(1) dw_d(1)
// The first 21 are the navigation states State.P_diag publishes.
// with the attitude error defined in the body frame: q_true = q (x) exp(dtheta / 2), i.e.
// R_true = R (I + [dtheta]x) to first order ("multiplicative" EKF: Markley, "Attitude error
// representations for Kalman filtering", JGCD 2003; Sola, "Quaternion kinematics for the
// error-state Kalman filter", 2017, sections 5 and 6).
//
// Continuous-time model (Sola 2017, eq. 235 with the local attitude error; Beard & McLain
// section 8.11 for the same full-state structure):
//   p_dot = v
//   v_dot = R (a_m - b_a - n_a) + g e3                       (a_m: measured specific force)
//   q_dot = 1/2 q (x) (0, w - n_g),  w = (I - S_g) (w_m - b_g)  (w_m: measured body rate)
//   b_g_dot = n_bg,  b_a_dot = n_ba,  wind_dot = n_w,  b_baro_dot = n_bb,  S_g_dot = n_S,
//   b_m_dot = n_bm,  k_sp_dot = n_sp   (random walks; b_m: the magnetometer's offset, k_sp: the
//   static port's error, measurements.hpp)
//   e_gnss_dot = -k e_gnss + n_e   (first-order Gauss-Markov: the slowly wandering GNSS position
//                                   error of Beard & McLain eq. 7.26, 1/k = 1100 s)
//   w_d_dot = -w_d / tau_w + n_wd  (first-order Gauss-Markov: the vertical gust)
// Error dynamics (first order in dx), with a = a_m - b_a, u = w_m - b_g and w = (I - S_g) u:
//   dp_dot     = dv
//   dv_dot     = -R [a]x dtheta - R db_a - R n_a
//   dtheta_dot = -[w]x dtheta - (I - S_g) db_g - U dS_g - n_g,   U = diag(u^T, u^T, u^T) (3x9)
// (the gyro scale-factor and cross-coupling states of an aided INS; observable only while the
// aircraft rotates: its turns and rolls show the filter what each axis's rate leaks into the
// others). The accelerometer's scale and cross-axis errors stay process noise (accel_scale): as states
// (S_a, 9 more) they improved the hourglass but let the aggressive mission's worst roll grow
// 1.4 -> 2.7 deg (bench_estimation, realistic, 10 seeds).
// Discrete transition over one IMU interval dt (Sola 2017, eq. 270 / 310):
//   F = I + A dt except the attitude block, which is exact: dtheta' = Exp(-w dt) dtheta - ...,
//   and the Gauss-Markov blocks, exp(-k dt) I and exp(-dt / tau_w).
// Discrete process noise: Q_v = (sigma_a dt)^2 I, Q_theta = (sigma_g dt)^2 I, where sigma_a and
// sigma_g are the per-sample standard deviations of the accelerometer and gyro (white noise of
// one sample held over dt); random walks: Q = sigma^2 dt with sigma in unit/sqrt(s).
// Covariance period (PX4 EKF2's FILTER_UPDATE_PERIOD_MS, 10 ms, over its accumulated delta
// angles and velocities): the nominal state moves with every IMU sample, the covariance once per
// covariance_period with the product of the samples' transitions, Phi = F_N ... F_1, kept on F's
// blocks: Phi_theta,theta (the accumulated body rotation's transpose), Phi_theta,bg and
// Phi_theta,S exactly (Phi_th,X <- F_th,th Phi_th,X + F_th,X); Phi_v,theta = sum -dt R [a]x
// Phi_theta,theta and Phi_v,ba = sum -dt R (first order in the period); Phi_p,v = T I (T the
// period's length). The blocks left out (p,theta; v,bg; v,S; ...) are second order in T
// (0.5 T^2 g = 0.5 mm/rad at 10 ms). Q is the sum of the samples' Q_i (not rotated within the
// period: the accelerometer and gyro noises are isotropic). Every update steps the covariance to
// the current sample first; with a period of 0 every sample steps it (Phi = F).
//
// Measurement update (any model of the shape described in measurements.hpp):
//   y = z - h(x),  S = H P H^T + R,  NIS = y^T S^-1 y (chi-square gate),
//   K = P H^T S^-1,  dx = K y,  x <- x [+] dx,
//   P <- (I - K H) P (I - K H)^T + K R K^T   (Joseph form; expanded, P - K H P - (K H P)^T +
//   K S K^T, its last two terms cancel for the optimal K: P - K (H P), a rank-M product), then
//   P <- (P + P^T) / 2.
// The covariance is therefore kept symmetric; it stays positive definite as long as R > 0 and
// the process noise is > 0 (checked by healthy()).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "tern/math.hpp"
#include "tern/param.hpp"

namespace tern::ekf {

inline constexpr int kErrDim = 35;  ///< error-state dimension

/// Offsets of the error-state blocks.
namespace idx {
inline constexpr int p = 0;    ///< position, 3
inline constexpr int v = 3;    ///< velocity, 3
inline constexpr int th = 6;   ///< attitude error (body frame), 3
inline constexpr int bg = 9;   ///< gyro bias, 3
inline constexpr int ba = 12;  ///< accelerometer bias, 3
inline constexpr int w = 15;   ///< wind north, east, 2
inline constexpr int bb = 17;  ///< barometer bias, 1
inline constexpr int eg = 18;  ///< GNSS position error, 3
inline constexpr int sg = 21;  ///< gyro sensitivity error S_g, 9, row by row (S_g(i, j) at sg + 3 i + j)
inline constexpr int bm = 30;  ///< magnetometer offset b_m, 3
inline constexpr int sp = 33;  ///< static-pressure error coefficient k_sp, 1
inline constexpr int wd = 34;  ///< vertical wind w_d, 1
}  // namespace idx

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using ErrVec = Eigen::Matrix<double, kErrDim, 1>;
using Cov = Eigen::Matrix<double, kErrDim, kErrDim>;
using Mat39 = Eigen::Matrix<double, 3, 9>;

/// U = diag(u^T, u^T, u^T): d((I - S_g) u) = -U dS_g for the row-by-row error dS_g (3x9).
inline Mat39 sensitivity_jacobian(const Vec3& u) {
  Mat39 U = Mat39::Zero();
  for (int i = 0; i < 3; ++i) U.block<1, 3>(i, 3 * i) = u.transpose();
  return U;
}

/// The estimated (nominal) state. Units and frames as in the file comment.
struct NominalState {
  Vec3 p = Vec3::Zero();
  Vec3 v = Vec3::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Vec3 b_g = Vec3::Zero();
  Vec3 b_a = Vec3::Zero();
  Eigen::Vector2d wind = Eigen::Vector2d::Zero();
  double b_baro = 0.0;
  Vec3 e_gnss = Vec3::Zero();
  Mat3 S_g = Mat3::Zero();
  /// Magnetometer offset (hard iron, the motor current's field, the calibration's residual) in
  /// body FRD, as a fraction of the Earth's field intensity (x field_strength = tesla).
  Vec3 b_m = Vec3::Zero();
  /// Static-pressure error coefficient (dimensionless): the static port reads the ambient
  /// pressure plus k_sp times the dynamic pressure (BaroAltitude).
  double k_sp = 0.0;
  /// Vertical wind (positive down), m/s.
  double wind_d = 0.0;

  /// The body rate (I - S_g) (gyro - b_g) from a gyro sample (body FRD, rad/s).
  Vec3 rate(const Vec3& gyro) const { return gyro - b_g - S_g * (gyro - b_g); }
  /// Rotation body FRD -> NED.
  Mat3 R() const { return q.toRotationMatrix(); }
  /// Wind vector in NED, m/s.
  Vec3 wind_ned() const { return {wind.x(), wind.y(), wind_d}; }
  /// Air-relative velocity in body FRD, (u_r, v_r, w_r) = R^T (v - w), m/s (Beard & McLain eq. 2.7).
  Vec3 air_velocity_body() const { return q.conjugate() * (v - wind_ned()); }
  bool all_finite() const {
    return p.allFinite() && v.allFinite() && q.coeffs().allFinite() && b_g.allFinite() && b_a.allFinite() && wind.allFinite() &&
           std::isfinite(b_baro) && e_gnss.allFinite() && S_g.allFinite() && b_m.allFinite() && std::isfinite(k_sp) &&
           std::isfinite(wind_d);
  }
};

/// Rotation vector -> unit quaternion (exponential map), exact for any angle.
inline Eigen::Quaterniond quat_exp(const Vec3& rotvec) {
  const double angle = rotvec.norm();
  if (angle < 1e-9) {
    return Eigen::Quaterniond(1.0, 0.5 * rotvec.x(), 0.5 * rotvec.y(), 0.5 * rotvec.z()).normalized();
  }
  const double s = std::sin(0.5 * angle) / angle;
  return Eigen::Quaterniond(std::cos(0.5 * angle), s * rotvec.x(), s * rotvec.y(), s * rotvec.z());
}

/// x [+] dx: applies an error-state correction to a nominal state (attitude multiplicatively).
NominalState boxplus(const NominalState& x, const ErrVec& dx);

/// P <- (P + P^T) / 2 in place, one pass over the strict upper triangle.
inline void symmetrize(Cov& P) {
  for (int j = 1; j < kErrDim; ++j) {
    for (int i = 0; i < j; ++i) {
      const double m = 0.5 * (P(i, j) + P(j, i));
      P(i, j) = m;
      P(j, i) = m;
    }
  }
}

/// Process-noise figures (see the file comment for how they enter Q).
struct ProcessNoise {
  /// Accelerometer white noise, 1 sigma per sample, m/s^2. In flight the propeller's vibration
  /// dominates the sensor's own noise (ICM-20602: 100 ug/sqrt(Hz) over ~157 Hz = 0.012 m/s^2);
  /// PX4 EKF2's default EKF2_ACC_NOISE, 0.35 m/s^2 per 100 Hz filter step, is 0.7 m/s^2 per 400 Hz
  /// sample; 1.0 adds margin for the 1-2 % scale and cross-axis errors (datasheet) of a 2-g turn.
  double accel = 1.0;
  /// Gyro white noise, 1 sigma per sample, rad/s: PX4 EKF2's EKF2_GYR_NOISE, 0.015 rad/s
  /// (vibration dominates the ICM-20602's own 4 mdps/sqrt(Hz) = 8.7e-4 rad/s per sample; the
  /// scale and cross-axis errors are states, S_g).
  double gyro = 0.015;
  /// Random walk of the gyro sensitivity error S_g, 1/sqrt(s): the sensitivity drifts slowly
  /// with temperature; 2e-5 lets it move 0.07 % in 20 minutes.
  double gyro_scale_walk = 2e-5;
  /// Accelerometer scale-factor, cross-axis and mounting error as a fraction of the specific
  /// force's departure from the level 1 g: the FCU's stored calibration (ROSflight
  /// Sensors::calibrate_accel) is taken level at rest and absorbs these errors there, what is left
  /// grows with the load (a 2-g turn: (M - I) g). ICM-20602 +-1 % sensitivity and +-2 % cross-axis
  /// (DS-000176) uniform within them, root-sum-square with the default imu_mount_sigma (1 deg):
  /// sqrt(0.013^2 + 0.0175^2) = 0.022. Enters as velocity random walk of density
  /// accel_scale load sqrt(maneuver_time).
  double accel_scale = 0.022;
  double maneuver_time = 0.3;     ///< s: how long a load is held (correlation time of the accelerometer
                                  ///< scale error's effect; 0.3 s: no divergence over 10 + 10 realistic
                                  ///< bench flights, 1 s: 1-3)
  double gyro_bias_walk = 5e-5;   ///< gyro-bias random walk, rad/s/sqrt(s) (a MEMS bias instability
                                  ///< of a few deg/h with margin; ROSflight's simulator: 5e-7)
  double accel_bias_walk = 1e-3;  ///< accelerometer-bias random walk, m/s^2/sqrt(s)
  /// Horizontal-wind random walk, m/s/sqrt(s): follows the gusts. A first-order gust of sigma
  /// with correlation time tau = L / Va wanders like a random walk of sigma sqrt(2 / tau) over
  /// less than tau: MIL-F-8785C moderate turbulence at 70 m, sigma_u = sigma_v = 2.3 m/s and
  /// L = 234 m, at 17 m/s 0.9; the lateral gust's spectrum (Dryden, second order) moves faster at
  /// the filter's time scale of seconds. 2.0: the wind takes up the gusts the attitude took
  /// (bench_estimation, aggressive mission, moderate turbulence, realistic, 10 seeds: roll
  /// median/worst 0.39/0.67 deg at 1.0, 0.30/0.58 at 2.0; 30-s GNSS outage worst drift 49 -> 31 m;
  /// 0.5: roll 0.61/0.94).
  double wind_walk = 2.0;
  double baro_bias_walk = 0.05;        ///< barometer-bias random walk, m/sqrt(s)
  double position = 0.0;               ///< extra position random walk (model error), m/sqrt(s)
  double gnss_error_walk_h = 0.066;    ///< GNSS horizontal error driving noise, m/sqrt(s) (ROSflight:
                                       ///< 0.21 m times T_s per 10 Hz fix = 0.21 sqrt(0.1))
  double gnss_error_walk_v = 0.126;    ///< GNSS vertical error driving noise, m/sqrt(s) (0.40 sqrt(0.1))
  double gnss_error_k = 1.0 / 1100.0;  ///< GNSS error Gauss-Markov rate k, 1/s
  /// Random walk of the magnetometer offset b_m, fraction of the field intensity per sqrt(s): the
  /// offset follows the motor current (throttle) and the temperature; 5e-4 lets it move 0.5 % of
  /// the field (0.25 uT) in 100 s. 2e-3 let the heading follow the wind's errors in turbulence
  /// (bench_estimation, aggressive, realistic, 10 seeds: worst yaw 2.18 against 1.82 deg).
  double mag_bias_walk = 5e-4;
  /// Random walk of the static-pressure error coefficient k_sp, 1/sqrt(s): the port's error
  /// changes with the angle of attack and sideslip the coefficient averages over.
  double static_error_walk = 1e-4;
  /// Vertical wind as a first-order Gauss-Markov process: steady sigma (m/s) and correlation
  /// time (s). MIL-F-8785C at low altitude: sigma_w = 0.1 W20, 0.77 m/s light and 1.5 m/s
  /// moderate turbulence; L_w = h (50 m in Beard & McLain's table 4.1), so L_w / Va = 3 s at 17 m/s.
  double vertical_wind_sigma = 1.5;
  double vertical_wind_time = 3.0;
  double vertical_wind_rate() const { return 1.0 / vertical_wind_time; }

  /// The plugin's parameter names and ranges (declare_struct, tern/param_struct.hpp); the member
  /// initialisers above are their defaults.
  template <class V>
  static void describe(V& v) {
    using tern::ParamSpec;
    using P = ProcessNoise;
    v(&P::accel, "accel_noise", ParamSpec("m/s^2", 1e-4, 10.0, "accelerometer white noise, 1 sigma per IMU sample"));
    v(&P::gyro, "gyro_noise", ParamSpec("rad/s", 1e-6, 1.0, "gyro white noise, 1 sigma per IMU sample"));
    v(&P::gyro_scale_walk, "gyro_scale_walk",
      ParamSpec("1/sqrt(s)", 0.0, 1.0, "random walk of the gyro sensitivity error (scale, cross-axis)"));
    v(&P::accel_scale, "accel_scale",
      ParamSpec("", 0.0, 0.5, "accelerometer scale, cross-axis and mounting error, fraction of the load beyond level 1 g"));
    v(&P::maneuver_time, "maneuver_time",
      ParamSpec("s", 0.0, 60.0, "how long a load is held: correlation time of the accelerometer scale error"));
    v(&P::gyro_bias_walk, "gyro_bias_walk", ParamSpec("rad/s/sqrt(s)", 0.0, 1.0, "gyro-bias random walk"));
    v(&P::accel_bias_walk, "accel_bias_walk", ParamSpec("m/s^2/sqrt(s)", 0.0, 10.0, "accelerometer-bias random walk"));
    v(&P::wind_walk, "wind_walk", ParamSpec("m/s/sqrt(s)", 0.0, 10.0, "horizontal-wind random walk"));
    v(&P::baro_bias_walk, "baro_bias_walk", ParamSpec("m/sqrt(s)", 0.0, 10.0, "barometer-bias random walk"));
    v(&P::position, "pos_process_noise", ParamSpec("m/sqrt(s)", 0.0, 10.0, "extra position random walk (model error)"));
    v(&P::gnss_error_walk_h, "gnss_error_walk_h",
      ParamSpec("m/sqrt(s)", 0.0, 100.0, "driving noise of the GNSS horizontal position error (Gauss-Markov state)"));
    v(&P::gnss_error_walk_v, "gnss_error_walk_v",
      ParamSpec("m/sqrt(s)", 0.0, 100.0, "driving noise of the GNSS vertical position error (Gauss-Markov state)"));
    v(&P::gnss_error_k, "gnss_error_rate",
      ParamSpec("1/s", 0.0, 10.0, "Gauss-Markov rate k of the GNSS position error (ROSflight k_gnss 1/1100)"));
    v(&P::mag_bias_walk, "mag_bias_walk",
      ParamSpec("1/sqrt(s)", 0.0, 1.0, "random walk of the magnetometer offset, fraction of the field intensity"));
    v(&P::vertical_wind_sigma, "vertical_wind_sigma", ParamSpec("m/s", 0.0, 20.0, "vertical gust, steady sigma (Gauss-Markov state)"));
    v(&P::vertical_wind_time, "vertical_wind_time", ParamSpec("s", 0.1, 600.0, "vertical gust correlation time"));
    v(&P::static_error_walk, "static_error_walk",
      ParamSpec("1/sqrt(s)", 0.0, 1.0, "random walk of the static-pressure error coefficient (fraction of the dynamic pressure)"));
  }
};

/// Outcome of one measurement update.
enum class UpdateResult : std::uint8_t {
  accepted,  ///< applied to the state
  rejected,  ///< failed the chi-square gate
  skipped,   ///< the model is not applicable now (e.g. airspeed below its minimum)
  invalid    ///< non-finite measurement, or innovation covariance not positive definite
};

/// Counters every measurement model keeps.
struct UpdateStats {
  std::uint64_t accepted = 0;
  std::uint64_t rejected = 0;  ///< by the chi-square gate
  std::uint64_t skipped = 0;
  std::uint64_t invalid = 0;
  std::uint64_t consecutive_rejected = 0;  ///< rejections since the last accepted update
  double last_nis = 0.0;                   ///< normalised innovation squared of the last gated update
  /// its innovation's first (up to) three components, as gated (at the measurement's time of validity)
  std::array<double, 3> last_innovation{};
  double nis_sum = 0.0;         ///< sum of the NIS of every gated update (accepted or rejected)...
  std::uint64_t nis_count = 0;  ///< ...and their number: mean NIS = nis_sum / nis_count
  double max_ratio = -1.0;      ///< largest NIS / gate since take_max_ratio() (-1: none)
  double mean_nis() const { return nis_count > 0 ? nis_sum / static_cast<double>(nis_count) : 0.0; }
  /// The largest test ratio since the last call, -1 when there was no gated update.
  double take_max_ratio() {
    const double r = max_ratio;
    max_ratio = -1.0;
    return r;
  }
};

/// The update's P -= W^T W (Filter::update): for each column j, W^T's columns m = 0 .. M-1
/// (contiguous, kErrDim each) times W^T(j, m) subtracted from P's column j in that order, one pass
/// over the column. Every element takes the same multiplications and subtractions whatever the
/// vector width, so the result does not depend on the machine (on x86-64 the function is also
/// built for AVX and chosen at load time where the CPU has it: filter.cpp).
void downdate(Cov& P, const double* Wt, int M);
/// The update's P H^T (kErrDim x M, column-major, into PHt): H's (M x kErrDim, column-major) non-zero
/// entries times P's columns, summed over P's columns in order (filter.cpp, as downdate()).
void P_times_Ht(const Cov& P, const double* H, int M, double* PHt);
/// Every element of P finite (their sum is: an overflow counts as not finite).
bool all_finite(const Cov& P);

/// The filter: nominal state, kErrDim x kErrDim covariance, propagation and the generic update.
class Filter {
 public:
  /// Sets the state and covariance (P0 must be symmetric positive definite).
  void initialize(const NominalState& x0, const Cov& P0) {
    x_ = x0;
    P_ = P0;
    P_symmetric_ = false;
    pending_ = Pending{};
  }

  /// Propagates over dt seconds (> 0) with one IMU sample: accel = measured specific force
  /// (body FRD, m/s^2), gyro = measured rate (body FRD, rad/s). Allocation free. The nominal
  /// state moves now; the covariance when the samples since its last step span the covariance
  /// period (file comment). Returns true when the covariance stepped.
  bool propagate(const Vec3& accel, const Vec3& gyro, double dt, const ProcessNoise& noise, double gravity);

  /// Covariance period, s (>= 0; 0: every sample). Steps the pending samples first.
  void set_covariance_period(double seconds) {
    step_covariance();
    covariance_period_ = std::max(seconds, 0.0);
  }
  double covariance_period() const { return covariance_period_; }
  /// Brings the covariance to the last propagated sample (no-op when it is there). update() and
  /// mutable_P() call it; P() does not (it is the covariance at the last step, at most one
  /// covariance period old).
  void step_covariance();

  /// The Gauss-Markov states' decays over dt: exp(-k dt) of the GNSS error, exp(-dt / tau_w) of
  /// the vertical wind, and 1 - exp(-2 dt / tau_w) (its discrete variance's factor).
  struct Decays {
    double gnss_error, vertical_wind, vertical_wind_var;
  };
  static Decays decays(const ProcessNoise& noise, double dt);

  /// The nominal-state part of propagate(): constant specific force and rate over dt (`d`: the
  /// decays over dt, computed when null).
  static NominalState propagate_nominal(const NominalState& x, const Vec3& accel, const Vec3& gyro, double dt, double gravity,
                                        const ProcessNoise& noise, const Decays* d = nullptr);
  /// The dense error-state transition F of propagate() with the Gauss-Markov rates of `noise` (for tests and documentation;
  /// propagate() applies it block-wise without forming it).
  static Cov transition(const NominalState& x, const Vec3& accel, const Vec3& gyro, double dt, const ProcessNoise& noise);
  /// The discrete process noise Q of propagate() (diagonal) at the specific force's departure
  /// |a - (0, 0, -g)| = load, m/s^2, from the level 1 g at which the accelerometer was calibrated.
  static ErrVec process_noise_diagonal(const ProcessNoise& noise, double dt, double load, const Decays* d = nullptr);

  /// Generic measurement update with a model (measurements.hpp describes the interface):
  /// residual z - h(x), Jacobian H, noise R, chi-square gate model.gate (<= 0: no gate).
  /// Delayed measurement (valid at an earlier time t_v): x_then is the state at t_v and
  /// corrected_since the sum of the corrections applied since (correction_sum() then and now);
  /// the residual is z - h(x_then) - H corrected_since, i.e. the innovation of x(t_v) as it
  /// would be with today's knowledge, and the correction is applied to the current state with
  /// the current covariance (the error state changes little over a fusion delay of a few tenths
  /// of a second; Sola 2017 sec. 7 for the error-state view).
  template <class Model>
  UpdateResult update(Model& model, const typename Model::Vec& z, const NominalState* x_then = nullptr,
                      const ErrVec* corrected_since = nullptr);

  /// Sum of every correction K y applied so far (error-state coordinates).
  const ErrVec& correction_sum() const { return correction_sum_; }

  /// Covariance inflation: adds (beta - 1) times their variance, as independent noise, to the
  /// n error states from `first` (beta >= 1; cross-covariances untouched, so P stays positive
  /// definite). Used when a sensor keeps being rejected because the filter is overconfident,
  /// instead of resetting the state: "this state drifted more than the model says". Scaling the
  /// rows and columns instead would also scale the correlations with the other states: for the
  /// GNSS position (z = p + e_gnss, p and e_gnss strongly anti-correlated) the next fix would
  /// then tell the filter it had learnt e_gnss (measured: position NEES 165).
  /// `cap` (n values, or null): no state's variance grows beyond cap[i] (the square of the
  /// innovation on its axis: the state drifted by at most the whole disagreement). Uncapped, a
  /// GNSS fix whose height the barometer keeps contradicting doubled the horizontal variances
  /// with every 10-Hz fix, the height's own inflation undone by the barometer each time.
  void inflate(int first, int n, double beta, const double* cap = nullptr) {
    step_covariance();
    for (int i = first; i < first + n; ++i) {
      double add = (beta - 1.0) * P_(i, i);
      if (cap != nullptr) add = std::min(add, std::max(0.0, cap[i - first] - P_(i, i)));
      P_(i, i) += add;
    }
  }

  /// Adds independent variance `var` (each >= 0) to the error states from `first`: a state that
  /// just changed by an unknown amount of that variance (the GNSS error when the receiver's
  /// satellites change). P stays positive definite.
  template <int N>
  void add_variance(int first, const Eigen::Matrix<double, N, 1>& var) {
    step_covariance();
    for (int i = 0; i < N; ++i) P_(first + i, first + i) += var(i);
  }

  /// Scales the error states from `first` by `a` in the covariance (P <- D P D, D = diag(a) there,
  /// 1 elsewhere): the covariance half of a linear transition e <- a e of those states (the
  /// caller moves their nominal values). P stays positive semi-definite.
  template <int N>
  void scale_covariance(int first, const Eigen::Matrix<double, N, 1>& a) {
    step_covariance();
    for (int i = 0; i < N; ++i) {
      P_.row(first + i) *= a(i);
      P_.col(first + i) *= a(i);
    }
  }

  /// Caps the variances of the n error states from `first` at max_var by scaling their rows and
  /// columns (P <- D P D with D diagonal: P stays positive definite, the correlation
  /// coefficients stay). For a random-walk state that no measurement reaches for a while (the
  /// wind on the ground, below the pitot's minimum airspeed): its variance would otherwise grow
  /// past any figure the state can physically take.
  void limit_variance(int first, int n, double max_var) {
    step_covariance();
    for (int i = first; i < first + n; ++i) {
      if (!(P_(i, i) > max_var)) continue;
      const double d = std::sqrt(max_var / P_(i, i));
      P_.row(i) *= d;
      P_.col(i) *= d;
    }
  }

  /// Applies an error-state correction without touching P (used by resets); it counts in
  /// correction_sum() like an update's.
  void inject(const ErrVec& dx) {
    x_ = boxplus(x_, dx);
    correction_sum_ += dx;
  }

  /// Covariance finite with a positive diagonal, state finite. (The sum of P is finite exactly
  /// when every element is, barring an overflow that is unhealthy too; it vectorises, where an
  /// element-wise check costs as much as the covariance propagation.)
  bool healthy() const { return all_finite(P_) && (P_.diagonal().array() > 0.0).all() && x_.all_finite(); }

  const NominalState& x() const { return x_; }
  /// The covariance as of its last step (at most one covariance period behind x()).
  const Cov& P() const { return P_; }
  NominalState& mutable_x() { return x_; }
  Cov& mutable_P() {
    step_covariance();
    P_symmetric_ = false;  // the caller's blocks may differ from their mirror by an ulp
    return P_;
  }

 private:
  /// The samples propagated since the covariance's last step: Phi's blocks and the summed Q.
  struct Pending {
    int samples = 0;
    double dt = 0.0;                ///< s, their total length
    Mat3 th_th = Mat3::Identity();  ///< Phi_theta,theta
    Mat3 th_bg = Mat3::Zero();      ///< Phi_theta,bg
    Mat39 th_sg = Mat39::Zero();    ///< Phi_theta,S
    Mat3 v_th = Mat3::Zero();       ///< Phi_v,theta
    Mat3 v_ba = Mat3::Zero();       ///< Phi_v,ba
    ErrVec q = ErrVec::Zero();      ///< sum of the samples' process noise (diagonal)
    double gnss_error_k = 0.0;      ///< the Gauss-Markov rates they were propagated with
    double vertical_wind_rate = 0.0;
  };
  void accumulate(const Vec3& a, const Vec3& w, const Vec3& u, double dt, const ProcessNoise& noise, double load);
  /// decays() for this dt and noise, remembered: the IMU's interval repeats sample after sample.
  const Decays& decays_for(const ProcessNoise& noise, double dt);

  NominalState x_;
  Cov P_ = Cov::Identity();
  /// P_ exactly symmetric: update(), step_covariance(), inflate() and limit_variance() keep it
  /// so; initialize() and mutable_P() may not (step_covariance() then symmetrises first).
  bool P_symmetric_ = true;
  ErrVec correction_sum_ = ErrVec::Zero();
  double covariance_period_ = 0.0;
  Pending pending_;
  struct {
    double dt = -1.0, gnss_error_k = 0.0, vertical_wind_time = 0.0;
    Decays d{};
  } decays_;
};

template <class Model>
UpdateResult Filter::update(Model& model, const typename Model::Vec& z, const NominalState* x_then, const ErrVec* corrected_since) {
  constexpr int M = Model::kDim;
  using VecM = Eigen::Matrix<double, M, 1>;
  using MatM = Eigen::Matrix<double, M, M>;
  using Jac = Eigen::Matrix<double, M, kErrDim>;
  if (!z.allFinite()) {
    ++model.stats.invalid;
    return UpdateResult::invalid;
  }
  if (!model.applicable(x_, z)) {
    ++model.stats.skipped;
    return UpdateResult::skipped;
  }
  step_covariance();
  const Jac H = model.jacobian(x_);
  VecM y = model.residual(x_then != nullptr ? *x_then : x_, z);
  if (corrected_since != nullptr) y -= H * *corrected_since;
  const MatM R = model.noise(x_);
  // (H P)^T = P H^T over H's non-zero columns only (a model touches a few states): P's column k
  // (contiguous) times H's column k, held as columns.
  Eigen::Matrix<double, kErrDim, M> HPt;
  P_times_Ht(P_, H.data(), M, HPt.data());
  const MatM S = H.lazyProduct(HPt) + R;  // coefficient-wise (Eigen's GEMM set-up cost more than the product)
  const Eigen::LLT<MatM> llt(S);
  if (!y.allFinite() || !S.allFinite() || llt.info() != Eigen::Success) {
    ++model.stats.invalid;
    return UpdateResult::invalid;
  }
  const double nis = y.dot(llt.solve(y));
  model.stats.last_nis = nis;
  for (int i = 0; i < std::min(M, 3); ++i) model.stats.last_innovation[static_cast<std::size_t>(i)] = y(i);
  model.stats.nis_sum += nis;
  ++model.stats.nis_count;
  if (model.gate > 0.0) model.stats.max_ratio = std::max(model.stats.max_ratio, nis / model.gate);
  if (model.gate > 0.0 && !(nis <= model.gate)) {
    ++model.stats.rejected;
    ++model.stats.consecutive_rejected;
    return UpdateResult::rejected;
  }
  // With S = L L^T (Cholesky) and W = L^-1 H P (M x n): K = P H^T S^-1 = W^T L^-1, and the
  // Joseph form P = (I - K H) P (I - K H)^T + K R K^T, expanded P - K H P - (K H P)^T + K S K^T,
  // is, for this (optimal) K, P - K H P = P - W^T W: a rank-M product, O(n^2 M) instead of
  // O(n^3). Column by column, vectorised over the rows, P(:, j) -= W^T W(:, j): element (i, j)
  // and (j, i) take the same products in the same order, so P stays exactly symmetric (the
  // (P + P^T) / 2 of the file comment) without a mirror.
  // (W^T held as its columns: contiguous, so the column updates vectorise; W^T = (HP)^T L^-T by
  // forward substitution over those columns)
  const MatM L = llt.matrixL();
  Eigen::Matrix<double, kErrDim, M>& Wt = HPt;
  for (int i = 0; i < M; ++i) {
    for (int k = 0; k < i; ++k) Wt.col(i) -= L(i, k) * Wt.col(k);
    Wt.col(i) /= L(i, i);
  }
  const ErrVec dx = Wt * llt.matrixL().solve(y);
  x_ = boxplus(x_, dx);
  correction_sum_ += dx;
  downdate(P_, Wt.data(), M);
  ++model.stats.accepted;
  model.stats.consecutive_rejected = 0;
  return UpdateResult::accepted;
}

}  // namespace tern::ekf
