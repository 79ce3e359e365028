// core/apps/dds/src/topic_tools.cpp: see topic_tools.hpp.
#include "topic_tools.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include <fmt/format.h>

#include "dds_bridge.hpp"

namespace tern::core {

std::optional<std::string> sample_field(const std::string& sample, const std::string& name, bool value_only) {
  std::istringstream in(sample);
  std::string line, out;
  bool found = false;
  while (std::getline(in, line)) {
    const auto colon = line.find(": ");
    if (colon == std::string::npos) continue;
    const std::string key = line.substr(0, colon);
    const bool exact = key == name;
    if (!exact && key.rfind(name + ".", 0) != 0) continue;
    found = true;
    out += (exact && value_only ? line.substr(colon + 2) : line) + "\n";
  }
  if (!found) return std::nullopt;
  return out;
}

void TopicRate::arrived(Clock::time_point t) {
  ++samples_;
  if (last_) {
    periods_.push_back(std::chrono::duration<double>(t - *last_).count());
    if (periods_.size() > window_) periods_.pop_front();
  }
  last_ = t;
}

std::string TopicRate::report() const {
  if (periods_.empty()) return "no new messages";
  const double n = static_cast<double>(periods_.size());
  const double mean = std::accumulate(periods_.begin(), periods_.end(), 0.0) / n;
  double var = 0;
  for (double p : periods_) var += (p - mean) * (p - mean);
  const auto [lo, hi] = std::minmax_element(periods_.begin(), periods_.end());
  return fmt::format("average rate: {:.3f}\n\tmin: {:.3f}s max: {:.3f}s std dev: {:.5f}s window: {}", mean > 0 ? 1.0 / mean : 0.0, *lo, *hi,
                     std::sqrt(var / n), periods_.size() + 1);
}

std::string describe_param(const DdsParam& p) {
  static const char* kTypes[] = {"bool", "integer", "double", "string", "double array"};  // ParamValue's order
  std::string s = fmt::format("{} ({}{})\n", p.name, kTypes[p.value.index()], p.unit.empty() ? "" : ", " + p.unit);
  s += fmt::format("  description: {}\n", p.description);
  s += fmt::format("  value: {}\n  default: {}\n", to_string(p.value), to_string(p.default_value));
  if (std::isfinite(p.min) && std::isfinite(p.max)) s += fmt::format("  range: [{}, {}]\n", p.min, p.max);
  s += p.read_only ? "  read-only in flight (start-only: set it between flights)\n" : "  changes in flight at the next tick\n";
  return s;
}

int topic_hz(DdsClient& client, const std::string& topic, std::optional<double> duration) {
  using Clock = TopicRate::Clock;
  TopicRate rate;
  Clock::time_point t0, next_report;  // from the first sample (finding the vehicle takes a while)
  client.echo(topic, [&](const std::string&) {
    const auto now = Clock::now();
    if (rate.samples() == 0) {
      t0 = now;
      next_report = now + std::chrono::seconds(1);
    }
    rate.arrived(now);
    const bool over = duration && std::chrono::duration<double>(now - t0).count() >= *duration;
    if (now >= next_report || over) {
      fmt::print("{}\n", rate.report());
      std::fflush(stdout);
      next_report = now + std::chrono::seconds(1);
    }
    return !over;
  });
  return 0;
}

}  // namespace tern::core
