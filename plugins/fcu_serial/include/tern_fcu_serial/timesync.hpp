// tern_fcu_serial/timesync.hpp: the FCU's clock mapped to the companion computer's clock with
// MAVLink TIMESYNC, as ROSflight's rosflight_io does it. Plain C++, no tern host types.
//
// The companion sends TIMESYNC{tc1 = 0, ts1 = its time in ns}; the FCU answers
// TIMESYNC{tc1 = FCU time in ns, ts1 = the request's ts1}. With the answer received at companion
// time t_rx, the round trip is rtt = t_rx - ts1 and, assuming a symmetric link, the offset
// sample is  offset = tc1 - (ts1 + t_rx) / 2  (FCU time - companion time). Samples are
// smoothed exponentially (weight `alpha` on the previous estimate); a sample whose round trip
// exceeds `max_rtt` is ignored; a sample farther than `reset_threshold` from the estimate
// (the FCU rebooted, or its clock jumped) replaces it and is counted in resets(). Every accepted
// round trip is kept for rtt_stats(): the companion-to-FCU-to-companion latency of the link,
// including the FCU's wait until its loop reads the request (ROSflight answers in
// CommManager::timesync_callback, called from ROSflight::run).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "tern_fcu_serial/messages.hpp"

namespace tern::fcu {

class TimeSync {
 public:
  struct Options {
    double alpha = 0.9;                          ///< smoothing weight of the previous estimate, 0..1
    std::int64_t max_rtt = 50'000'000;           ///< ns: slower answers are ignored
    std::int64_t reset_threshold = 100'000'000;  ///< ns: a larger jump restarts the estimate
  };
  TimeSync() = default;
  explicit TimeSync(Options o) : opt_(o) {}

  /// The request to send at companion time now_ns.
  static mavlink::Timesync request(std::int64_t now_ns) {
    mavlink::Timesync m;
    m.tc1 = 0;
    m.ts1 = now_ns;
    return m;
  }
  /// What an FCU answers to request `req` at its time fcu_ns (nullopt if req is itself an answer).
  static std::optional<mavlink::Timesync> respond(const mavlink::Timesync& req, std::int64_t fcu_ns) {
    if (req.tc1 != 0) return std::nullopt;
    mavlink::Timesync m;
    m.tc1 = fcu_ns;
    m.ts1 = req.ts1;
    return m;
  }

  /// Feeds an answer received at companion time rx_ns. Returns true if the estimate changed.
  bool on_answer(const mavlink::Timesync& m, std::int64_t rx_ns) {
    if (m.tc1 == 0) return false;  // a request, not an answer
    const std::int64_t rtt = rx_ns - m.ts1;
    if (rtt < 0 || rtt > opt_.max_rtt) {
      ++rejected_;
      return false;
    }
    const std::int64_t sample = m.tc1 - (m.ts1 + rtt / 2);
    last_rtt_ = rtt;
    rtts_.push_back(rtt);
    ++samples_;
    if (!offset_) {
      offset_ = sample;
      return true;
    }
    const std::int64_t diff = sample - *offset_;
    if (diff > opt_.reset_threshold || diff < -opt_.reset_threshold) {
      offset_ = sample;
      ++resets_;
      return true;
    }
    offset_ = *offset_ + std::llround((1.0 - opt_.alpha) * static_cast<double>(diff));
    return true;
  }

  bool synced() const { return offset_.has_value(); }
  /// FCU time - companion time, ns (0 before the first answer).
  std::int64_t offset() const { return offset_.value_or(0); }
  std::int64_t to_companion(std::int64_t fcu_ns) const { return fcu_ns - offset(); }
  std::int64_t to_fcu(std::int64_t companion_ns) const { return companion_ns + offset(); }
  std::int64_t last_rtt() const { return last_rtt_; }
  std::uint64_t samples() const { return samples_; }
  std::uint64_t rejected() const { return rejected_; }
  std::uint64_t resets() const { return resets_; }

  /// Round trips of the accepted answers, ns: nearest-rank 50th and 99th percentiles and the
  /// largest (all 0 without answers).
  struct RttStats {
    std::int64_t p50 = 0, p99 = 0, max = 0;
    std::size_t count = 0;
  };
  RttStats rtt_stats() const {
    RttStats r;
    r.count = rtts_.size();
    if (rtts_.empty()) return r;
    std::vector<std::int64_t> v = rtts_;
    std::sort(v.begin(), v.end());
    auto rank = [&](double q) { return v[static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size()))) - 1]; };
    r.p50 = rank(0.50);
    r.p99 = rank(0.99);
    r.max = v.back();
    return r;
  }
  void clear() { offset_.reset(); }

 private:
  Options opt_;
  std::optional<std::int64_t> offset_;
  std::int64_t last_rtt_ = 0;
  std::vector<std::int64_t> rtts_;  ///< accepted round trips, ns (10 Hz of requests: 288 kB an hour)
  std::uint64_t samples_ = 0, rejected_ = 0, resets_ = 0;
};

}  // namespace tern::fcu
