// The replay report's row account (RowAccount, replay_report.hpp): every row of the log's sensor
// tables against what the estimator received, from summary.json's instances `replay` (the
// replay source's <topic>_rows and <topic>_played) and the estimator's (<sensor>_received,
// <sensor>_invalid, <input>_missed).
#include <cmath>

#include "replay/replay_report_parts.hpp"

namespace tern::core::replay_report {

RowAccount row_account(const nlohmann::ordered_json& summary, const EstimatorCounters& counters) {
  RowAccount a;
  const auto instance = [&](const std::string& name) -> const nlohmann::ordered_json* {
    if (!summary.contains("instances") || !summary["instances"].contains(name)) return nullptr;
    const auto& i = summary["instances"][name];
    return i.is_object() ? &i : nullptr;
  };
  const nlohmann::ordered_json* replay = instance("replay");
  const nlohmann::ordered_json* est = counters.instance.empty() ? nullptr : instance(counters.instance);
  if (replay == nullptr || est == nullptr) {
    a.absent =
        replay == nullptr ? "absent (summary.json has no replay instance)" : "absent (summary.json names no estimator with counters)";
    return a;
  }
  const auto number = [](const nlohmann::ordered_json& o, const std::string& key) {
    return o.contains(key) && o[key].is_number() ? o[key].get<double>() : 0.0;
  };
  for (const char* topic : {"imu", "gnss", "baro", "diff_pressure", "mag"}) {
    const std::string t = topic;
    if (!replay->contains(t + "_rows")) continue;
    TopicRows r{t,
                number(*replay, t + "_rows"),
                number(*replay, t + "_played"),
                number(*est, t + "_received"),
                number(*est, t + "_invalid"),
                number(*est, t + "_missed")};
    a.lost += r.lost();
    a.not_played += r.rows - r.played;
    a.topics.push_back(r);
  }
  return a;
}

}  // namespace tern::core::replay_report
