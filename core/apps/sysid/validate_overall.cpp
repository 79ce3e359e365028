// core/apps/sysid/validate_overall.cpp: the files' overall scores, to rank them (validate.hpp, "Overall").
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "sysid/validate.hpp"

namespace tern::core::sysid {

OverallScores overall_scores(const std::vector<AircraftScore>& files) {
  OverallScores out;
  std::vector<std::size_t> used;
  for (std::size_t c = 0; c < kChannels; ++c) {
    const bool everywhere = !files.empty() && std::all_of(files.begin(), files.end(), [c](const AircraftScore& f) {
      return std::isfinite(f.fit[c].nrmse) && f.fit[c].nrmse >= 0.0;
    });
    if (everywhere) used.push_back(c), out.channels.emplace_back(kChannelSpecs[c].name);
  }
  for (const AircraftScore& f : files) {
    double log_sum = 0.0;
    for (const std::size_t c : used) log_sum += std::log(std::max(f.fit[c].nrmse, 1e-12));
    out.nrmse.push_back(used.empty() ? std::numeric_limits<double>::quiet_NaN() : std::exp(log_sum / static_cast<double>(used.size())));
  }
  out.ranking.resize(files.size());
  std::iota(out.ranking.begin(), out.ranking.end(), std::size_t{0});
  std::stable_sort(out.ranking.begin(), out.ranking.end(), [&](std::size_t a, std::size_t b) {
    const double x = out.nrmse[a], y = out.nrmse[b];
    return std::isfinite(x) && (!std::isfinite(y) || x < y);
  });
  return out;
}

}  // namespace tern::core::sysid
