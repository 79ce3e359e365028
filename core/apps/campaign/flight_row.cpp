#include "flight_row.hpp"

#include <cmath>
#include <optional>

#include <fmt/format.h>

namespace tern::campaign {

namespace {

void flatten(const nlohmann::ordered_json& j, const std::string& prefix, std::vector<Figure>& out) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string key = prefix.empty() ? it.key() : prefix + "." + it.key();
    const auto& v = it.value();
    if (v.is_object()) {
      flatten(v, key, out);
    } else if (v.is_array()) {
      out.push_back({key + ".count", std::to_string(v.size()), static_cast<double>(v.size())});
    } else if (v.is_boolean()) {
      out.push_back({key, v.get<bool>() ? "true" : "false", v.get<bool>() ? 1.0 : 0.0});
    } else if (v.is_number()) {
      const double d = v.get<double>();
      out.push_back({key, v.is_number_float() ? number_text(d) : v.dump(), d});
    } else if (v.is_string()) {
      out.push_back({key, v.get<std::string>(), NAN});
    } else {
      out.push_back({key, "", NAN});  // null: no value (e.g. an RMSE with no samples)
    }
  }
}

bool holds(double a, const std::string& op, double b) {
  if (op == "<") return a < b;
  if (op == "<=") return a <= b;
  if (op == ">") return a > b;
  if (op == ">=") return a >= b;
  if (op == "==") return a == b;
  return a != b;
}

std::optional<double> as_number(const std::string& s) {
  if (s == "true") return 1.0;
  if (s == "false") return 0.0;
  try {
    std::size_t used = 0;
    const double d = std::stod(s, &used);
    if (used == s.size()) return d;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

}  // namespace

const char* outcome_name(Outcome o) { return o == Outcome::pass ? "pass" : o == Outcome::fail ? "fail" : "error"; }

const Figure* FlightRow::find(const std::string& name) const {
  for (const auto& f : figures)
    if (f.name == name) return &f;
  return nullptr;
}

std::vector<Figure> flatten_summary(const nlohmann::ordered_json& summary) {
  nlohmann::ordered_json s = summary;
  if (s.contains("instances"))
    for (auto& [name, inst] : s["instances"].items()) {
      inst.erase("plugin");
      inst.erase("library");
      inst.erase("library_fnv1a");
    }
  std::vector<Figure> out;
  flatten(s, "", out);
  return out;
}

void judge(const std::vector<Criterion>& criteria, FlightRow& row) {
  std::vector<std::string> failed;
  for (const auto& c : criteria) {
    const Figure* f = row.find(c.figure);
    if (f == nullptr) {
      failed.push_back(fmt::format("{}: no such figure in summary.json", c.text));
      continue;
    }
    const auto want = as_number(c.value);
    const auto have = as_number(f->text);
    bool ok;
    if (want && have) {
      ok = holds(*have, c.op, *want);
    } else {
      ok = (c.op == "==") == (f->text == c.value);
      if (c.op != "==" && c.op != "!=") ok = false;
    }
    if (!ok) failed.push_back(fmt::format("{} = {} (needs {} {})", c.figure, f->text.empty() ? "null" : f->text, c.op, c.value));
  }
  row.outcome = failed.empty() ? Outcome::pass : Outcome::fail;
  row.why = fmt::format("{}", fmt::join(failed, "; "));
}

}  // namespace tern::campaign
