// core/apps/campaign/flight_row.hpp: one flight's row of the campaign table: what it drew, what
// its summary.json says (flattened), and whether it passed the campaign's criteria.
//
// Flattening: nested keys joined with '.' ("metrics.max_cross_track_m",
// "instances.sim.crash_speed"); a list becomes its length ("phases.count"); the instances'
// plugin names and library paths/hashes are left out (provenance, in summary.json). A
// criterion "FIGURE OP VALUE" compares numbers (true/false count as 1/0) or, with == and !=,
// text; a figure missing from the summary fails the criterion and says so.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "campaign_file.hpp"
#include "dispersion.hpp"

namespace tern::campaign {

/// A summary figure: its text as the table writes it; number NaN when not numeric.
struct Figure {
  std::string name, text;
  double number;
};

enum class Outcome { pass, fail, error };  ///< error: the flight left no complete summary
const char* outcome_name(Outcome o);

struct FlightRow {
  std::size_t index = 0;
  std::uint64_t seed = 0;
  std::string command;
  std::vector<Drawn> drawn;
  std::vector<Figure> figures;
  Outcome outcome = Outcome::error;
  std::string why;  ///< the criteria that failed, with the values ("" when passed)
  const Figure* find(const std::string& name) const;
};

/// summary.json flattened, in the document's order.
std::vector<Figure> flatten_summary(const nlohmann::ordered_json& summary);

/// Evaluates the criteria on row.figures; sets outcome and why.
void judge(const std::vector<Criterion>& criteria, FlightRow& row);

}  // namespace tern::campaign
