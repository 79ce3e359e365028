// core/apps/dds/include/topic_tools.hpp: what `tern echo --field` and `tern hz` do with the samples of
// a topic (issue 20, item 5), apart from DDS so that they can be tested alone.
//   sample_field: the lines of a rendered sample ("name: value", one per field, nested fields
//                 as "header.stamp", "quat.x") that belong to field NAME;
//   TopicRate:    the receive rate of a topic over a sliding window of arrival times, as
//                 `ros2 topic hz` reports it (average rate, min/max period, std dev of the period).
#pragma once

#include <chrono>
#include <cstddef>
#include <deque>
#include <optional>
#include <string>

namespace tern::core {

class DdsClient;
struct DdsParam;

/// `tern param describe NAME`: the descriptor as lines ("slc.roll_kp (double, rad/rad)\n  ...").
std::string describe_param(const DdsParam& p);

/// The "NAME: value" line of `sample` (or, for a nested field such as "quat", every "quat.*"
/// line), values only when `value_only`; nullopt when the sample has no such field.
std::optional<std::string> sample_field(const std::string& sample, const std::string& name, bool value_only = true);

class TopicRate {
 public:
  using Clock = std::chrono::steady_clock;
  /// `window`: how many of the latest periods the statistics cover (ros2 topic hz: 10000).
  explicit TopicRate(std::size_t window = 10000) : window_(window) {}
  void arrived(Clock::time_point t);
  /// Samples seen so far (the first one starts the clock: rates need two).
  std::size_t samples() const { return samples_; }
  /// "average rate: 400.012\n\tmin: 0.002s max: 0.003s std dev: 0.00011s window: 401", as
  /// ros2 topic hz prints it; "no new messages" before the second sample.
  std::string report() const;

 private:
  std::size_t window_;
  std::size_t samples_ = 0;
  std::optional<Clock::time_point> last_;
  std::deque<double> periods_;  // s
};

/// `tern hz TOPIC`: prints the rate report on stdout once a second (checked as samples arrive)
/// until `duration` seconds have passed since the first sample (nullopt: until interrupted). Returns 0; DdsError when no
/// sample arrives within the client's time-out.
int topic_hz(DdsClient& client, const std::string& topic, std::optional<double> duration);

}  // namespace tern::core
