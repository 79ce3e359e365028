// Estimator's fusion templates (estimator.hpp: fuse, fuse_now_or_then, fuse_robust), included by
// the files whose sensors they fuse. Private to the plugin.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>

#include "tern/estimator_ekf/estimator.hpp"

namespace tern::ekf {

template <class Model>
UpdateResult Estimator::fuse(Model& model, const typename Model::Vec& z, Nanos t_v) {
  // Dead reckoning (GNSS timed out): the air data and the magnetometer still correct the
  // position through its correlations with velocity, wind and heading, by up to a metre per
  // update; the published position takes those corrections in smoothly, like GNSS's return.
  const bool dead_reckoning = counters_[static_cast<int>(Sensor::gnss)].timed_out && cfg_.gnss_recovery_time > 0.0;
  const Vec3 p_before = filter_.x().p;
  const UpdateResult r = fuse_now_or_then(model, z, t_v);
  if (dead_reckoning && r == UpdateResult::accepted) output_offset_ -= filter_.x().p - p_before;
  return r;
}

template <class Model>
UpdateResult Estimator::fuse_now_or_then(Model& model, const typename Model::Vec& z, Nanos t_v) {
  if (t_v >= imu_stamp_) return filter_.update(model, z);
  const StateHistory::Entry* e = history_.at(t_v);
  if (e == nullptr) {
    ++model.stats.invalid;
    return UpdateResult::invalid;
  }
  NominalState x = e->x;
  x.p += x.v * to_seconds(t_v - e->stamp);
  const ErrVec since = filter_.correction_sum() - e->correction_sum;
  return filter_.update(model, z, &x, &since);
}

template <class Model>
UpdateResult Estimator::fuse_robust(Sensor s, Model& model, const typename Model::Vec& z, Nanos t_v, int first, int n) {
  const UpdateResult r = fuse(model, z, t_v);
  if (r != UpdateResult::rejected || model.stats.consecutive_rejected < static_cast<std::uint64_t>(cfg_.inflate_after)) return r;
  // The filter keeps disagreeing with the sensor: it is more likely overconfident than the
  // sensor wrong for this long. Inflate the variances of the states the sensor measures so the
  // innovation sits near the gate, and fuse again.
  const double beta = std::min(model.stats.last_nis / model.gate, 1e4);
  // each state's variance at most the square of the innovation on its axis (Filter::inflate), the
  // innovation as gated: at the measurement's time of validity
  std::array<double, 3> cap{};
  for (std::size_t i = 0; i < cap.size(); ++i) cap[i] = model.stats.last_innovation[i] * model.stats.last_innovation[i];
  filter_.inflate(first, n, beta, Model::kDim == n && n <= 3 ? cap.data() : nullptr);
  ++inflations_;
  double& worst = inflation_max_[static_cast<std::size_t>(s)];
  worst = std::max(worst, beta);
  push(imu_stamp_, EventKind::inflated, s, beta);
  return fuse(model, z, t_v);
}

}  // namespace tern::ekf
