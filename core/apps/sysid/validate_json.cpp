// core/apps/sysid/validate_json.cpp: DIR/validate.json, every figure of a `tern validate` run per
// aircraft file and channel, the windows, and what produced the numbers (validate_report.hpp).
#include <cmath>

#include "sysid/validate_report.hpp"

namespace tern::core::sysid {

namespace {

using nlohmann::ordered_json;

ordered_json number(double v) { return std::isfinite(v) ? ordered_json(v) : ordered_json(nullptr); }

ordered_json method_json(const ValidationRun& run) {
  return {{"estimate", run.estimate},
          {"series",
           {{"filter_hz", run.series.filter_hz},
            {"rate_hz", run.series.rate_hz},
            {"rule",
             "the log on the IMU's time base (core/apps/sysid/flight_data.hpp): commands in force through each file's servo lag, "
             "every channel through one zero-phase low-pass"}}},
          {"simulation",
           "sim_aero's uavbook model (tern/aero/model.hpp) open loop: each window starts from the logged state, the estimator's "
           "wind at its first sample held steady, the logged commands held between samples, RK4 in steps of at most max_step_s"},
          {"window_s", run.options.window_s},
          {"airborne", run.airborne},
          {"min_height_m", run.options.ground.min_height},
          {"min_Va_mps", run.options.min_Va},
          {"max_step_s", run.options.max_step},
          {"nrmse", "RMS(predicted - measured) / std(measured), population std over the scored samples"},
          {"theil_u", "RMS(predicted - measured) / (RMS(measured) + RMS(predicted)) (Theil's inequality coefficient)"},
          {"one_step",
           "RMS of measured - model at the logged state, inputs and wind of each scored sample: specific force and angular "
           "acceleration; as coefficients m da / (qbar S), (J dw) / (qbar S b|c|b)"},
          {"scored", "every window sample but its first"}};
}

ordered_json windows_json(const ValidationRun& run) {
  ordered_json list = ordered_json::array();
  for (const Window& w : run.windows)
    list.push_back({{"t_begin", run.t[w.begin]}, {"t_end", run.t[w.end - 1]}, {"samples", w.end - w.begin}});
  return list;
}

ordered_json file_json(const AircraftScore& f) {
  ordered_json channels = ordered_json::object();
  for (std::size_t c = 0; c < kChannels; ++c)
    channels[kChannelSpecs[c].name] = {{"unit", kChannelSpecs[c].unit},
                                       {"nrmse", number(f.fit[c].nrmse)},
                                       {"theil_u", number(f.fit[c].theil_u)},
                                       {"rms_error", number(f.fit[c].rms_error)},
                                       {"std_measured", number(f.fit[c].std_measured)},
                                       {"samples", f.fit[c].samples}};
  ordered_json one_step = ordered_json::object();
  for (std::size_t a = 0; a < kAxes; ++a)
    one_step[kAxisSpecs[a].name] = {{"unit", kAxisSpecs[a].unit},
                                    {"rms", number(f.one_step[a].rms)},
                                    {"coefficient", kAxisSpecs[a].coefficient},
                                    {"coefficient_rms", number(f.one_step[a].coefficient_rms)},
                                    {"samples", f.one_step[a].samples}};
  return {{"file", f.file},       {"name", f.name},      {"servo_tau_s", f.servo_tau}, {"diverged_windows", f.prediction.diverged},
          {"channels", channels}, {"one_step", one_step}};
}

}  // namespace

ordered_json validate_json(const ValidationRun& run) {
  const OverallScores overall = overall_scores(run.files);
  ordered_json files = ordered_json::array(), ranking = ordered_json::array();
  for (std::size_t i = 0; i < run.files.size(); ++i) {
    files.push_back(file_json(run.files[i]));
    files.back()["overall_nrmse"] = number(overall.nrmse[i]);
  }
  for (const std::size_t i : overall.ranking) ranking.push_back(run.files[i].file);
  return {{"log", run.log},
          {"method", method_json(run)},
          {"scored_samples", scored_samples(run.windows)},
          {"scored_seconds", scored_seconds(run)},
          {"windows", windows_json(run)},
          {"overall",
           {{"rule", "per file the geometric mean of its NRMSE over `channels` (finite for every file); ranking: the files, best first"},
            {"channels", overall.channels},
            {"ranking", ranking}}},
          {"aircraft", files}};
}

}  // namespace tern::core::sysid
