// core/apps/campaign/campaign_report.hpp: the campaign's table and summary.
//
//   <out>/results.csv    one row per flight, by index: index, seed, outcome (pass|fail|error),
//                        why, the re-fly command, every drawn value ("name [unit]"), every
//                        summary.json figure (flight_row.hpp). Deterministic: the same campaign
//                        gives the same bytes whatever the engine, order or worker count.
//   <out>/summary.json   pass rate with its 95 % Wilson score interval (Wilson 1927; errors
//                        count as failures), percentiles (5, 50, 95) of every numeric figure,
//                        the worst flights with their commands (deterministic too)
//   <out>/summary.md     the same for people
//   <out>/throughput.json  wall time, flights/min, aggregate real-time factor, overhead (varies)
#pragma once

#include <filesystem>
#include <utility>
#include <vector>

#include "campaign_file.hpp"
#include "flight_row.hpp"

namespace tern::campaign {

/// 95 % Wilson score interval of `passed` successes in `n` trials ({0, 1} when n = 0).
std::pair<double, double> wilson95(std::size_t passed, std::size_t n);

/// Percentile q in [0, 1] of sorted values, linear between order statistics (numpy's default).
double percentile(const std::vector<double>& sorted, double q);

/// The rows ranked worst first: errors, then failures, then by `worst_by` (larger is worse
/// unless a criterion on it reads > or >=), then by index.
std::vector<const FlightRow*> worst_first(const CampaignFile& c, const std::vector<FlightRow>& rows);

/// Writes results.csv, summary.json and summary.md into `out`. Throws core::ConfigError if it
/// cannot write.
void write_report(const CampaignFile& c, const std::vector<FlightRow>& rows, const fs::path& out);

}  // namespace tern::campaign
