#include "campaign_report.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "config/error.hpp"
#include "files/log_file.hpp"

namespace tern::campaign {

namespace {

constexpr std::size_t kWorstShown = 5;

std::string csv(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

/// Replaced at once (log_file.hpp's temp file + rename); a failure is one ConfigError line.
void write_file(const fs::path& p, const std::string& text) {
  core::LogHealth health;
  if (!core::write_file_atomically(p, text, health)) throw core::ConfigError(health.error());
}

std::string results_csv(const std::vector<FlightRow>& rows) {
  std::vector<std::pair<std::string, std::string>> drawn, figures;
  std::map<std::string, bool> seen_d, seen_f;
  for (const auto& r : rows) {
    for (const auto& d : r.drawn)
      if (!seen_d[d.column]) seen_d[d.column] = true, drawn.emplace_back(d.column, d.unit);
    for (const auto& f : r.figures)
      if (!seen_f[f.name]) seen_f[f.name] = true, figures.emplace_back(f.name, "");
  }
  std::string s = "index,seed,outcome,why,command";
  for (const auto& [name, unit] : drawn) s += "," + csv(unit.empty() ? name : name + " [" + unit + "]");
  for (const auto& [name, unit] : figures) s += "," + csv(name);
  s += "\n";
  for (const auto& r : rows) {
    s += fmt::format("{},{},{},{},{}", r.index, r.seed, outcome_name(r.outcome), csv(r.why), csv(r.command));
    for (const auto& [name, unit] : drawn) {
      std::string v;
      for (const auto& d : r.drawn)
        if (d.column == name) v = d.text;
      s += "," + csv(v);
    }
    for (const auto& [name, unit] : figures) {
      const Figure* f = r.find(name);
      s += "," + csv(f ? f->text : "");
    }
    s += "\n";
  }
  return s;
}

nlohmann::ordered_json figure_stats(const std::vector<FlightRow>& rows) {
  std::vector<std::string> names;
  std::map<std::string, std::vector<double>> values;
  for (const auto& r : rows)
    for (const auto& f : r.figures) {
      if (!std::isfinite(f.number) || f.name == "seed" || f.name == "flight") continue;
      if (!values.count(f.name)) names.push_back(f.name);
      values[f.name].push_back(f.number);
    }
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (const auto& n : names) {
    auto& v = values[n];
    std::sort(v.begin(), v.end());
    double sum = 0;
    for (double x : v) sum += x;
    out[n] = {{"n", v.size()},
              {"min", v.front()},
              {"p5", percentile(v, 0.05)},
              {"p50", percentile(v, 0.5)},
              {"p95", percentile(v, 0.95)},
              {"max", v.back()},
              {"mean", sum / static_cast<double>(v.size())}};
  }
  return out;
}

}  // namespace

std::pair<double, double> wilson95(std::size_t passed, std::size_t n) {
  if (n == 0) return {0.0, 1.0};
  const double z = 1.959963984540054, nn = static_cast<double>(n), p = static_cast<double>(passed) / nn;
  const double denom = 1 + z * z / nn;
  const double centre = (p + z * z / (2 * nn)) / denom;
  const double half = z / denom * std::sqrt(p * (1 - p) / nn + z * z / (4 * nn * nn));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

double percentile(const std::vector<double>& v, double q) {
  if (v.empty()) return NAN;
  const double pos = q * static_cast<double>(v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(std::floor(pos));
  if (i + 1 >= v.size()) return v.back();
  return v[i] + (pos - static_cast<double>(i)) * (v[i + 1] - v[i]);
}

std::vector<const FlightRow*> worst_first(const CampaignFile& c, const std::vector<FlightRow>& rows) {
  bool larger_worse = true;
  for (const auto& cr : c.criteria)
    if (cr.figure == c.worst_by && (cr.op == ">" || cr.op == ">=")) larger_worse = false;
  auto key = [&](const FlightRow* r) {
    const Figure* f = c.worst_by.empty() ? nullptr : r->find(c.worst_by);
    const double v = f && std::isfinite(f->number) ? f->number : -INFINITY;
    return larger_worse ? v : (f ? -v : -INFINITY);
  };
  auto rank = [](Outcome o) { return o == Outcome::error ? 0 : o == Outcome::fail ? 1 : 2; };
  std::vector<const FlightRow*> out;
  for (const auto& r : rows) out.push_back(&r);
  std::stable_sort(out.begin(), out.end(), [&](const FlightRow* a, const FlightRow* b) {
    if (rank(a->outcome) != rank(b->outcome)) return rank(a->outcome) < rank(b->outcome);
    return key(a) > key(b);
  });
  return out;
}

void write_report(const CampaignFile& c, const std::vector<FlightRow>& rows, const fs::path& out) {
  write_file(out / "results.csv", results_csv(rows));
  std::size_t passed = 0, failed = 0, errors = 0;
  for (const auto& r : rows) (r.outcome == Outcome::pass ? passed : r.outcome == Outcome::fail ? failed : errors)++;
  const auto [lo, hi] = wilson95(passed, rows.size());
  nlohmann::ordered_json j;
  j["campaign"] = c.name;
  j["file"] = c.file.string();
  j["base"] = c.base.string();
  j["seed"] = c.seed;
  j["flights_planned"] = c.flights;
  j["flights"] = rows.size();
  j["passed"] = passed;
  j["failed"] = failed;
  j["errors"] = errors;
  j["pass_rate"] = rows.empty() ? 0.0 : static_cast<double>(passed) / static_cast<double>(rows.size());
  j["pass_rate_ci95"] = {lo, hi};
  j["criteria"] = nlohmann::ordered_json::array();
  for (const auto& cr : c.criteria) j["criteria"].push_back(cr.text);
  j["worst_by"] = c.worst_by;
  const auto worst = worst_first(c, rows);
  auto w = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < std::min(kWorstShown, worst.size()); ++i) {
    const FlightRow& r = *worst[i];
    const Figure* f = c.worst_by.empty() ? nullptr : r.find(c.worst_by);
    w.push_back({{"index", r.index},
                 {"seed", r.seed},
                 {"outcome", outcome_name(r.outcome)},
                 {"why", r.why},
                 {c.worst_by.empty() ? "worst_by" : c.worst_by, f ? f->text : ""},
                 {"command", r.command}});
  }
  j["worst"] = w;
  j["figures"] = figure_stats(rows);
  write_file(out / "summary.json", j.dump(2) + "\n");

  std::string md = fmt::format(
      "# Campaign {}\n\n{} flights of {} (seed {}, base {}): **{} passed ({:.1f} %, 95 % CI {:.1f}-{:.1f} %)**, {} failed, {} errors.\n\n",
      c.name, rows.size(), c.file.filename().string(), c.seed, c.base.filename().string(), passed, 100.0 * j["pass_rate"].get<double>(),
      100 * lo, 100 * hi, failed, errors);
  md += "Criteria: " +
        (c.criteria.empty() ? std::string("none") : fmt::format("`{}`", fmt::join(j["criteria"].get<std::vector<std::string>>(), "`, `"))) +
        "\n\n";
  md += "## Worst flights\n\n| flight | outcome | " + (c.worst_by.empty() ? std::string("-") : c.worst_by) +
        " | why | re-fly |\n|---|---|---|---|---|\n";
  for (const auto& x : w)
    md += fmt::format("| {} | {} | {} | {} | `{}` |\n", x["index"].get<std::size_t>(), x["outcome"].get<std::string>(),
                      c.worst_by.empty() ? "" : x[c.worst_by].get<std::string>(), x["why"].get<std::string>(),
                      x["command"].get<std::string>());
  md += "\n## Figures (over the flights that have them)\n\n| figure | n | p5 | p50 | p95 | max |\n|---|---|---|---|---|---|\n";
  for (const auto& [name, s] : j["figures"].items())
    md += fmt::format("| {} | {} | {:.4g} | {:.4g} | {:.4g} | {:.4g} |\n", name, s["n"].get<std::size_t>(), s["p5"].get<double>(),
                      s["p50"].get<double>(), s["p95"].get<double>(), s["max"].get<double>());
  write_file(out / "summary.md", md);
}

}  // namespace tern::campaign
