#include "campaign_file.hpp"

#include <algorithm>
#include <cmath>
#include <regex>

#include <fmt/format.h>

#include "config/config.hpp"
#include "config/error.hpp"
#include "tern/input_file.hpp"

namespace tern::campaign {

using core::ConfigError;
using core::where;

namespace {

std::string text_of(const YAML::Node& n) { return n.IsScalar() ? n.Scalar() : n.IsMap() ? "<map>" : n.IsSequence() ? "<list>" : "<null>"; }

double number(const YAML::Node& n, const fs::path& f, const std::string& field) {
  try {
    if (n.IsScalar()) {
      const double v = n.as<double>();
      if (std::isfinite(v)) return v;
    }
  } catch (const YAML::Exception&) {
  }
  throw ConfigError(where(f, n) + field + ": expected a number, got '" + text_of(n) + "'");
}

/// A number or a list of numbers.
std::vector<double> numbers(const YAML::Node& n, const fs::path& f, const std::string& field) {
  if (!n) throw ConfigError(f.string() + ": " + field + ": missing");
  if (!n.IsSequence()) return {number(n, f, field)};
  std::vector<double> v;
  for (std::size_t i = 0; i < n.size(); ++i) v.push_back(number(n[i], f, fmt::format("{}[{}]", field, i)));
  if (v.empty()) throw ConfigError(where(f, n) + field + ": expected a number or a non-empty list of numbers");
  return v;
}

std::pair<double, double> interval(const YAML::Node& n, const fs::path& f, const std::string& field) {
  const std::vector<double> v = n ? numbers(n, f, field) : std::vector<double>{};
  if (v.size() != 2 || v[0] > v[1])
    throw ConfigError((n ? where(f, n) : f.string() + ": ") + field + ": expected [low, high] with low <= high");
  return {v[0], v[1]};
}

void same_size(const std::vector<double>& a, const std::vector<double>& b, const YAML::Node& n, const fs::path& f,
               const std::string& field) {
  if (a.size() != b.size() && a.size() != 1 && b.size() != 1)
    throw ConfigError(where(f, n) + field + fmt::format(": bounds of different sizes ({} and {})", a.size(), b.size()));
}

Dispersion dispersion(const std::string& target, const YAML::Node& n, const fs::path& f) {
  const std::string field = "dispersions." + target;
  if (!n.IsMap()) throw ConfigError(where(f, n) + field + ": expected a map {dist: ..., ...}");
  Dispersion d;
  d.target = target;
  d.node = n;
  if (!n["dist"]) throw ConfigError(where(f, n) + field + ": missing 'dist' (uniform, normal, choice, grid or polar)");
  const std::string dist = text_of(n["dist"]);
  const YAML::Node rel = n["relative"];
  const bool relative = rel && core::yaml_bool(rel, f, field + ".relative");
  d.relative = d.aircraft() || relative;
  if (d.aircraft() && rel && !relative)
    throw ConfigError(where(f, rel) + field + ".relative: aircraft perturbations are relative (value x (1 + draw))");
  if (dist == "uniform") {
    core::check_keys(n, f, field, {"dist", "low", "high", "relative"});
    d.low = numbers(n["low"], f, field + ".low");
    d.high = numbers(n["high"], f, field + ".high");
    same_size(d.low, d.high, n, f, field);
    for (std::size_t i = 0; i < std::max(d.low.size(), d.high.size()); ++i) {
      const double lo = d.low[d.low.size() == 1 ? 0 : i], hi = d.high[d.high.size() == 1 ? 0 : i];
      if (lo > hi) throw ConfigError(where(f, n["high"]) + field + fmt::format(".high: {} is below low {}", hi, lo));
    }
  } else if (dist == "normal") {
    core::check_keys(n, f, field, {"dist", "mean", "sd", "clip", "relative"});
    d.dist = Dist::normal;
    d.mean = numbers(n["mean"], f, field + ".mean");
    d.sd = numbers(n["sd"], f, field + ".sd");
    same_size(d.mean, d.sd, n, f, field);
    for (double s : d.sd)
      if (s < 0) throw ConfigError(where(f, n["sd"]) + field + fmt::format(".sd: must be >= 0, got {}", s));
    if (n["clip"]) d.clip = interval(n["clip"], f, field + ".clip");
  } else if (dist == "choice" || dist == "grid") {
    core::check_keys(n, f, field,
                     dist == "choice" ? std::vector<std::string>{"dist", "values", "weights", "relative"}
                                      : std::vector<std::string>{"dist", "values", "relative"});
    d.dist = dist == "choice" ? Dist::choice : Dist::grid;
    const YAML::Node v = n["values"];
    if (!v || !v.IsSequence() || v.size() == 0) throw ConfigError(where(f, v ? v : n) + field + ".values: expected a non-empty list");
    for (const auto& e : v) d.values.push_back(e);
    if (n["weights"]) {
      d.weights = numbers(n["weights"], f, field + ".weights");
      double sum = 0;
      for (double w : d.weights) sum += w < 0 ? NAN : w;
      if (d.weights.size() != d.values.size() || !(sum > 0))
        throw ConfigError(where(f, n["weights"]) + field + ".weights: expected one weight >= 0 per value, not all 0");
    }
  } else if (dist == "polar") {
    core::check_keys(n, f, field, {"dist", "speed", "from_deg", "into_wind"});
    d.dist = Dist::polar;
    d.speed = interval(n["speed"], f, field + ".speed");
    if (n["from_deg"]) d.from_deg = interval(n["from_deg"], f, field + ".from_deg");
    if (n["into_wind"]) d.into_wind = text_of(n["into_wind"]);
    if (d.aircraft()) throw ConfigError(where(f, n) + field + ": polar is for a vector parameter of an instance");
  } else {
    throw ConfigError(where(f, n["dist"]) + field + ".dist: '" + dist + "' is not uniform, normal, choice, grid or polar");
  }
  return d;
}

Criterion criterion(const YAML::Node& n, const fs::path& f, std::size_t i) {
  static const std::regex re(R"(^\s*([A-Za-z_][A-Za-z0-9_.]*)\s*(<=|>=|==|!=|<|>)\s*(\S+)\s*$)");
  const std::string field = fmt::format("criteria[{}]", i);
  std::smatch m;
  const std::string s = n.IsScalar() ? n.Scalar() : "";
  if (!std::regex_match(s, m, re))
    throw ConfigError(where(f, n) + field + ": '" + text_of(n) +
                      "' is not 'FIGURE OP VALUE' (OP: < <= > >= == !=), e.g. metrics.max_cross_track_m < 15");
  Criterion c{m[1], m[2], m[3], s};
  const bool numeric_op = c.op != "==" && c.op != "!=";
  if (numeric_op) {
    try {
      std::size_t used = 0;
      (void)std::stod(c.value, &used);
      if (used != c.value.size()) throw std::invalid_argument("");
    } catch (const std::exception&) {
      throw ConfigError(where(f, n) + field + ": '" + c.value + "' after " + c.op + " is not a number");
    }
  }
  return c;
}

}  // namespace

CampaignFile load_campaign(const fs::path& file_in) {
  CampaignFile c;
  c.file = fs::absolute(file_in).lexically_normal();
  const fs::path& f = c.file;
  if (!fs::exists(f)) throw ConfigError("campaign file '" + f.string() + "' not found");
  YAML::Node root;
  try {
    root = load_yaml_file(f, "campaign file");  // a regular file, bounded (tern/input_file.hpp)
  } catch (const std::runtime_error& e) {
    throw ConfigError(e.what());
  }
  if (!root.IsMap()) throw ConfigError(f.string() + ": a campaign file is a map of key: value");
  core::check_keys(root, f, "", {"name", "base", "seed", "flights", "duration", "log", "dispersions", "criteria", "worst_by"});
  c.name = root["name"] ? text_of(root["name"]) : f.stem().string();
  // the output directory's name (campaigns/<name>): one plain folder name, nothing above it
  if (c.name.empty() || c.name == "." || c.name == ".." || c.name.find('/') != std::string::npos ||
      std::any_of(c.name.begin(), c.name.end(), [](char ch) { return static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f; }))
    throw ConfigError((root["name"] ? where(f, root["name"]) : f.string() + ": ") + "name: '" + printable(c.name) +
                      "' is not a folder name (it names the output directory campaigns/<name>)");
  if (!root["base"]) throw ConfigError(f.string() + ": base: missing (the mission config every flight flies)");
  c.base = (f.parent_path() / text_of(root["base"])).lexically_normal();
  std::error_code ec;  // (a name too long for the file system: not found, not an exception)
  if (!fs::exists(c.base, ec)) throw ConfigError(where(f, root["base"]) + "base: '" + printable(c.base.string()) + "' not found");
  if (root["seed"]) {
    const auto s = root["seed"].IsScalar() ? core::parse_seed(root["seed"].Scalar()) : std::nullopt;
    if (!s) throw ConfigError(where(f, root["seed"]) + "seed: expected an integer 0 .. 2^64-1, got '" + text_of(root["seed"]) + "'");
    c.seed = *s;
  }
  if (root["duration"]) {
    c.duration = number(root["duration"], f, "duration");
    if (const std::string p = core::duration_problem(*c.duration); !p.empty())
      throw ConfigError(where(f, root["duration"]) + "duration: " + p);
  }
  if (root["log"]) {
    c.log_level = text_of(root["log"]);
    if (!core::log_level_from_name(c.log_level))
      throw ConfigError(where(f, root["log"]) + "log: expected " + core::log_level_names() + ", got '" + c.log_level + "'");
  }
  if (const YAML::Node ds = root["dispersions"]) {
    if (!ds.IsMap()) throw ConfigError(where(f, ds) + "dispersions: expected a map PARAMETER: {dist: ...}");
    for (const auto& kv : ds) c.dispersions.push_back(dispersion(kv.first.Scalar(), kv.second, f));
  }
  for (const auto& d : c.dispersions) {
    if (d.dist != Dist::grid) continue;
    if (c.grid_points > kMaxFlights / d.values.size())  // (the product would also wrap past 2^64)
      throw ConfigError(where(f, d.node) + "dispersions: " + d.target +
                        fmt::format(": the grid would have more than {:.0e} points (the product of the grid dispersions' sizes)",
                                    static_cast<double>(kMaxFlights)));
    c.grid_points *= d.values.size();
  }
  c.flights = c.grid_points;
  if (const YAML::Node n = root["flights"]) {
    const double v = number(n, f, "flights");
    if (!(v >= 1 && v <= static_cast<double>(kMaxFlights) && v == std::floor(v)))
      throw ConfigError(where(f, n) + "flights: expected a whole number >= 1, got '" + n.Scalar() + "'");
    c.flights = static_cast<std::size_t>(v);
  }
  if (const YAML::Node cr = root["criteria"]) {
    if (!cr.IsSequence()) throw ConfigError(where(f, cr) + "criteria: expected a list of 'FIGURE OP VALUE'");
    for (std::size_t i = 0; i < cr.size(); ++i) c.criteria.push_back(criterion(cr[i], f, i));
  }
  for (const auto& cr : c.criteria)
    if (c.worst_by.empty() && cr.op != "==" && cr.op != "!=") c.worst_by = cr.figure;
  if (root["worst_by"]) c.worst_by = text_of(root["worst_by"]);
  return c;
}

}  // namespace tern::campaign
