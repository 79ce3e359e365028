// tern/estimator_ekf/history.hpp: the recent past of the filter, for measurements fused at their
// time of validity (a GNSS fix arrives 0.1-0.2 s after the instant it describes).
//
// One entry per IMU sample: the stamp, the nominal state after that sample's propagation and the
// filter's correction sum at that moment (Filter::correction_sum()). A measurement valid at t_v
// is fused with the entry at or just before t_v (its position advanced by v (t_v - stamp)) and
// the corrections applied since (sum now - sum then): Filter::update(model, z, &x, &since).
// A fixed-size ring buffer: push() and at() never allocate. Plain C++ and Eigen.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <vector>

#include "tern/estimator_ekf/filter.hpp"
#include "tern/time.hpp"

namespace tern::ekf {

class StateHistory {
 public:
  struct Entry {
    Nanos stamp = 0;
    NominalState x;
    ErrVec correction_sum = ErrVec::Zero();
  };

  /// capacity: entries kept (at 400 Hz, 256 entries cover 0.64 s of delay). Throws
  /// std::invalid_argument if capacity is 0.
  explicit StateHistory(std::size_t capacity = 256) : buf_(capacity) {
    if (capacity == 0) throw std::invalid_argument("StateHistory: capacity must be > 0");
  }

  void clear() { size_ = 0; }
  std::size_t size() const { return size_; }
  bool full() const { return size_ == buf_.size(); }

  /// Appends the state at `stamp` (stamps increase); the oldest entry goes when full.
  void push(Nanos stamp, const NominalState& x, const ErrVec& correction_sum) {
    head_ = (head_ + 1) % buf_.size();
    Entry& e = buf_[head_];
    e.stamp = stamp;
    e.x = x;
    e.correction_sum = correction_sum;
    if (size_ < buf_.size()) ++size_;
  }

  /// The newest entry with stamp <= t, or nullptr when t is older than every entry.
  const Entry* at(Nanos t) const {
    // Binary search over age: k = 0 is the newest entry.
    if (size_ == 0 || entry(size_ - 1).stamp > t) return nullptr;
    std::size_t lo = 0, hi = size_ - 1;  // entry(hi).stamp <= t holds
    while (lo < hi) {
      const std::size_t mid = (lo + hi) / 2;
      if (entry(mid).stamp <= t)
        hi = mid;
      else
        lo = mid + 1;
    }
    return &entry(lo);
  }

 private:
  /// The k-th newest entry (k < size()).
  const Entry& entry(std::size_t k) const { return buf_[(head_ + buf_.size() - k) % buf_.size()]; }

  std::vector<Entry> buf_;
  std::size_t head_ = 0;
  std::size_t size_ = 0;
};

}  // namespace tern::ekf
