#include "line_manager.hpp"

namespace tern_@NAME@ {

void LineManager::set_waypoints(std::vector<Eigen::Vector3d> w, bool loop) {
  w_.clear();
  for (const auto& x : w)
    if (x.allFinite() && (w_.empty() || (x - w_.back()).norm() >= 1.0)) w_.push_back(x);
  if (loop && w_.size() > 2 && (w_.front() - w_.back()).norm() < 1.0) w_.pop_back();
  loop_ = loop;
  done_ = false;
  i_ = 1;
}

Segment LineManager::orbit_at(const Eigen::Vector3d& c, int index) const {
  Segment s;
  s.type = Segment::orbit;
  s.c = c;
  s.rho = orbit_radius;
  s.index = index;
  return s;
}

Segment LineManager::update(const Eigen::Vector3d& p) {
  const std::size_t n = w_.size();
  if (n == 0) return orbit_at(Eigen::Vector3d(0, 0, -loiter_altitude), -1);
  if (n == 1) return orbit_at(w_[0], 0);
  if (done_) return orbit_at(w_[n - 1], static_cast<int>(n - 1));

  // Algorithm 5: the half plane at w_i, normal to the bisector of the two segments. Indices
  // are modulo n when the mission loops (the closing segment w_{n-1} -> w_0 included).
  const std::size_t prev = (i_ + n - 1) % n;
  const Eigen::Vector3d q_prev = (w_[i_] - w_[prev]).normalized();
  if (!loop_ && i_ + 1 == n) {
    if ((p - w_[i_]).dot(q_prev) >= 0.0) {  // passed the last waypoint
      done_ = true;
      return orbit_at(w_[i_], static_cast<int>(i_));
    }
  } else {
    const std::size_t next = (i_ + 1) % n;
    const Eigen::Vector3d q_i = (w_[next] - w_[i_]).normalized();
    Eigen::Vector3d n_i = q_prev + q_i;
    n_i = n_i.norm() > 1e-9 ? n_i.normalized() : q_prev;  // reversal: switch on passing w_i
    if ((p - w_[i_]).dot(n_i) >= 0.0) i_ = next;
  }
  Segment s;
  s.r = w_[(i_ + n - 1) % n];
  s.q = (w_[i_] - s.r).normalized();
  s.index = static_cast<int>(i_);
  return s;
}

}  // namespace tern_@NAME@
