// The replay report's NIS section: innovations.csv's test ratios (NIS / gate, -1 when nothing was
// fused) turned back into NIS with the gate params.csv gives, per measurement, over the whole
// replay and over the window.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "replay/replay_report_parts.hpp"

namespace tern::core::replay_report {

namespace {

/// A measurement model that may write an innovations column, and its gate parameter ("" with
/// fixed_gate: a model without a gate parameter).
struct Candidate {
  std::string model, param;
  double fixed_gate = NAN;
};

/// estimator_ekf's models behind each column (plugins/estimator_ekf/src/health.cpp
/// take_innovations): mag is the heading or the 3-axis model, sideslip the side-force or the
/// zero-sideslip model. NormalForce has no gate parameter: its gate is the default 1-dof
/// chi-square 99.9 % quantile, 10.828 (estimator_ekf/measurements.hpp kChi2_999[1]).
std::vector<Candidate> candidates(const std::string& column) {
  if (column == "mag") return {{"mag", "mag_gate"}, {"mag_heading", "mag_heading_gate"}};
  if (column == "sideslip") return {{"side_force", "side_force_gate"}, {"sideslip", "sideslip_gate"}};
  if (column == "normal_force") return {{"normal_force", "", 10.828}};
  return {{column, column + "_gate"}};
}

double fused(const EstimatorCounters& c, const std::string& model) {
  for (const auto& m : c.models)
    if (m.model == model) return (std::isnan(m.accepted) ? 0.0 : m.accepted) + (std::isnan(m.rejected) ? 0.0 : m.rejected);
  return -1.0;  // no counters for this model
}

/// The estimator's parameter prefix: summary.json's instance, else the instance params.csv holds
/// a gnss_pos_gate for.
std::string prefix(const RunTables& run, const EstimatorCounters& c) {
  if (!c.instance.empty()) return c.instance + ".";
  for (const auto& [name, values] : run.params.values) {
    const auto dot = name.rfind('.');
    if (dot != std::string::npos && name.substr(dot + 1) == "gnss_pos_gate") return name.substr(0, dot + 1);
  }
  return "";
}

/// Which model wrote the column: the one candidate the counters show fused, else (one candidate
/// only) that one. nullopt with `why` otherwise.
std::optional<Candidate> pick(const std::string& column, const EstimatorCounters& c, std::string& why) {
  const auto all = candidates(column);
  std::vector<Candidate> used;
  for (const auto& k : all)
    if (fused(c, k.model) > 0) used.push_back(k);
  if (used.size() == 1) return used.front();
  if (used.empty() && all.size() == 1) return all.front();
  std::vector<std::string> names;
  for (const auto& k : used.empty() ? all : used) names.push_back(fmt::format("{} ({:.0f} fused)", k.model, fused(c, k.model)));
  why = fmt::format("gate unknown: {} {}; test-ratio figures only", used.empty() ? "no counters tell which of" : "both",
                    fmt::join(names, used.empty() ? " or " : " and "));
  return std::nullopt;
}

NisStats stats(const std::vector<double>& ratios, const std::vector<double>& nis) {
  NisStats s;
  s.count = ratios.size();
  if (s.count == 0) return s;
  s.rejected = static_cast<std::size_t>(std::count_if(ratios.begin(), ratios.end(), [](double r) { return r > 1.0; }));
  s.share_rejected = static_cast<double>(s.rejected) / static_cast<double>(s.count);
  s.p50_ratio = percentile(ratios, 0.50);
  s.p95_ratio = percentile(ratios, 0.95);
  s.p99_ratio = percentile(ratios, 0.99);
  if (nis.size() != ratios.size()) return s;  // the gate is unknown for some
  double sum = 0.0;
  for (double x : nis) sum += x;
  s.mean_nis = sum / static_cast<double>(nis.size());
  s.p50_nis = percentile(nis, 0.50);
  s.p95_nis = percentile(nis, 0.95);
  s.p99_nis = percentile(nis, 0.99);
  return s;
}

MeasurementReport one_column(const RunTables& run, const std::string& column, const EstimatorCounters& c, const ReplayWindow& w) {
  MeasurementReport m;
  m.name = column;
  std::string why;
  const auto model = pick(column, c, why);
  const std::string param = model && !model->param.empty() ? prefix(run, c) + model->param : "";
  if (model && model->param.empty())
    m.gate = fmt::format("{}: fixed gate {} (chi-square 1 dof, 99.9 %; no parameter)", model->model, model->fixed_gate);
  const auto& t = run.innovations->at("t");
  const auto& ratio = run.innovations->at(column);
  std::vector<double> r_all, n_all, r_win, n_win;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (!(ratio[k] >= 0.0)) continue;  // -1: nothing fused since the previous message
    const bool in = t[k] >= w.start_s && t[k] <= w.end_s;
    r_all.push_back(ratio[k]);
    if (in) r_win.push_back(ratio[k]);
    const double gate = !model ? NAN : model->param.empty() ? model->fixed_gate : run.params.number_at(param, t[k]).value_or(NAN);
    if (!(gate > 0.0)) continue;
    n_all.push_back(ratio[k] * gate);
    if (in) n_win.push_back(ratio[k] * gate);
  }
  if (model && !model->param.empty()) {
    const auto g0 = run.params.number_at(param, t.front());
    m.gate = !g0       ? fmt::format("gate unknown: params.csv has no number for {}; test-ratio figures only", param)
             : *g0 > 0 ? fmt::format("{} = {}{}", param, *g0,
                                     run.params.values.at(param).size() > 1 ? " (changed in flight: the value at each time)" : "")
                       : fmt::format("{} = {} (off): test-ratio figures only", param, *g0);
  }
  if (!model) m.gate = why;
  m.whole = stats(r_all, n_all);
  m.window = stats(r_win, n_win);
  return m;
}

}  // namespace

std::vector<MeasurementReport> measurement_reports(const RunTables& run, const EstimatorCounters& c, const ReplayWindow& w) {
  std::vector<MeasurementReport> out;
  if (!run.innovations) return out;
  for (const auto& [column, values] : run.innovations->columns)
    if (column != "t" && column != "stamp") out.push_back(one_column(run, column, c, w));
  const std::vector<std::string> order{"gnss_pos", "gnss_vel", "baro", "diff_pressure", "mag", "sideslip", "normal_force"};
  auto rank = [&](const MeasurementReport& m) { return std::find(order.begin(), order.end(), m.name) - order.begin(); };
  std::stable_sort(out.begin(), out.end(), [&](const auto& a, const auto& b) { return rank(a) < rank(b); });
  return out;
}

}  // namespace tern::core::replay_report
