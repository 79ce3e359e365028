// tern/estimator_ekf/yaw_gsf.hpp: the yaw from the IMU and the GNSS velocity alone, without a
// magnetometer: a Gaussian sum of five small EKFs, each started at another heading.
//
// The method of PX4 EKF2's EKFGSF_yaw (P. Riseborough, PX4-ECL EKF/EKFGSF_yaw.cpp): each model has
// its own attitude (a complementary filter: gyro, tilt corrected towards the low-passed specific
// force, with a fixed wing's centripetal acceleration V x omega removed) and a 3-state EKF
// [v_n, v_e, psi] that integrates the specific force rotated by that attitude and fuses the GNSS
// horizontal velocity. A model whose yaw is wrong predicts the velocity changes of every turn
// and every acceleration wrongly; its weight (the Gaussian density of its innovations) falls. The
// sum's yaw is the weighted circular mean, its variance the weighted spread plus the models' own.
// It needs manoeuvres (turns, speed changes) in the air to converge, within 5-20 s of a turn.
//
// Use (Estimator): predict() with every IMU sample, fuse_velocity() with every GNSS fix while
// flying, stop() on the ground. Units: SI, body FRD, NED, yaw in rad from north.
#pragma once

#include <array>

#include <Eigen/Core>
#include "tern/math.hpp"

namespace tern::ekf {

class YawGsf {
 public:
  static constexpr int kModels = 5;
  struct Config {
    double gyro_noise = 0.1;       ///< rad/s: yaw-rate noise of each model (PX4: 0.1)
    double accel_noise = 2.0;      ///< m/s^2: horizontal acceleration noise of each model (PX4: 2.0)
    double tilt_gain = 0.2;        ///< 1/s: complementary filter's tilt correction at 1 g (PX4: 0.2)
    double gyro_bias_gain = 0.04;  ///< 1/s: its gyro-bias integral gain (PX4: 0.04)
    double gravity = kGravity;     ///< m/s^2
  };

  YawGsf() = default;
  explicit YawGsf(const Config& c) : c_(c) {}

  /// One IMU sample: specific force (m/s^2) and angular rate (rad/s, with the main filter's gyro
  /// bias removed: the models' own bias learning sees only the tilt axes), body FRD, over dt s;
  /// `airspeed` (m/s, 0 when unknown or on the ground) removes the centripetal acceleration.
  void predict(const Eigen::Vector3d& accel, const Eigen::Vector3d& gyro, double dt, double airspeed);
  /// A GNSS horizontal velocity (NE, m/s) with its 1-sigma noise, while flying. The first one
  /// after a stop() starts the models (at their five headings) from it.
  void fuse_velocity(const Eigen::Vector2d& v_ne, double sigma);
  /// On the ground (operator handling, a vehicle's steel): the models wait to fly again.
  void stop() { fusing_ = false; }
  /// Fusing velocities and the models' attitudes are aligned.
  bool active() const { return fusing_; }
  double yaw() const { return yaw_; }                    ///< rad, (-pi, pi]
  double yaw_variance() const { return yaw_variance_; }  ///< rad^2 (pi^2 / 4 before any fusion)

 private:
  struct Model {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< body -> NED
    Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
    Eigen::Vector3d x = Eigen::Vector3d::Zero();  ///< v_n, v_e, psi
    Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
    double weight = 1.0 / kModels;
  };
  void align_tilt(const Eigen::Vector3d& accel);
  void start(const Eigen::Vector2d& v_ne, double sigma);
  double accel_gain() const;
  void predict_attitude(Model& m, const Eigen::Vector3d& gyro, double dt, double airspeed) const;
  void predict_ekf(Model& m, const Eigen::Vector3d& dv_body, double dt) const;
  /// Fuses v_ne into `m`; returns the Gaussian density of its innovation (0 if S is singular).
  double update_ekf(Model& m, const Eigen::Vector2d& v_ne, double sigma) const;
  void combine();

  Config c_;
  std::array<Model, kModels> models_{};
  Eigen::Vector3d accel_lp_ = Eigen::Vector3d::Zero();  ///< low-passed specific force, body
  double airspeed_ = 0.0;                               ///< of the last predict(), m/s
  bool tilt_aligned_ = false;
  bool fusing_ = false;
  double yaw_ = 0.0;
  double yaw_variance_ = 2.4674011002723395;  // (pi/2)^2
};

}  // namespace tern::ekf
