// `tern tune`: see tune.hpp.
#include "commands/tune.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "config/error.hpp"
#include "flight/host.hpp"
#include "files/log_file.hpp"
#include "tern/math.hpp"

namespace tern::core {

namespace {

// Defaults: steps a well-tuned small aircraft (the Anaconda, ROSplane's gains) answers in a
// fraction of the half period, inside its limits (roll_max 45 deg, theta limits, 12-25 m/s).
constexpr std::array<TuneLoop, 5> kLoops{{
    {"roll", "phi_c", "phi", "rad", 0.3491, 6.0, true},        // +-10 deg about wings level
    {"pitch", "theta_c", "theta", "rad", 0.1745, 6.0, false},  // +-5 deg about the trim pitch
    {"course", "chi_c", "chi", "rad", 0.5236, 40.0, false},    // +-15 deg
    {"altitude", "h_c", "h", "m", 10.0, 60.0, false},          // +-5 m
    {"airspeed", "Va_c", "Va", "m/s", 3.0, 40.0, false},       // +-1.5 m/s
}};

constexpr std::string_view kFollowerTopic = "follower_command";
constexpr std::string_view kCommandTopic = "controller_command";

double command_of(const TuneLoop& l, const msg::ControllerCommand& c) {
  if (l.symbol == "phi_c") return c.phi_c;
  if (l.symbol == "theta_c") return c.theta_c;
  if (l.symbol == "chi_c") return c.chi_c;
  if (l.symbol == "h_c") return c.h_c;
  return c.Va_c;
}

/// The response on the command's branch (a course within pi of its command).
double response_of(const TuneLoop& l, const msg::State& s, double command) {
  if (l.state == "phi") return s.phi;
  if (l.state == "theta") return s.theta;
  if (l.state == "chi") return unwrap_near(s.chi, command);
  if (l.state == "h") return s.altitude();
  return s.Va;
}

/// The instance whose output publishes `controller_command` (the path follower), found by
/// configuring the mission without flying.
const InstanceConfig& command_producer(const MissionConfig& mc) {
  HostOptions describe;
  describe.describing = true;
  describe.quiet = true;
  Host host(mc, describe);
  host.build();
  for (const auto& inst : host.instances()) {
    if (inst->builtin || inst->routed || inst->idle) continue;
    for (const auto* out : inst->plugin->outputs())
      if (out->topic() == kCommandTopic) return mc.plugins.at(inst->cfg.index);
  }
  throw ConfigError(fmt::format("{}: no instance (other than a controller) publishes {}: nothing for the signal generator to take over",
                                mc.file.string(), kCommandTopic));
}

ParamSetting setting(const MissionConfig& mc, YAML::Node value, const std::string& what) {
  return ParamSetting{std::move(value), mc.file, "tern tune " + what};
}

/// Remaps the follower's command to follower_command and adds the generator after it, in the
/// structs and in the YAML the flight log records (so that the run's config.yaml re-flies it).
void insert_generator(MissionConfig& mc, const TuneLoop& l, double amplitude, double period, double start_time) {
  const std::string name = "signal";
  for (const auto& p : mc.plugins)
    if (p.name == name) throw ConfigError(fmt::format("{}: an instance is already named '{}'", mc.file.string(), name));
  const InstanceConfig& follower = command_producer(mc);
  mc.plugins.at(follower.index).remap[std::string(kCommandTopic)] = std::string(kFollowerTopic);
  mc.root["plugins"][follower.index]["remap"][std::string(kCommandTopic)] = std::string(kFollowerTopic);

  InstanceConfig gen;
  gen.index = mc.plugins.size();
  gen.name = name;
  gen.plugin = "signal_generator";
  gen.rate = follower.rate.value_or(100.0);
  YAML::Node params;
  params["loop"] = std::string(l.name);
  params["waveform"] = "square";
  params["amplitude"] = amplitude;
  params["offset"] = -amplitude / 2.0;
  params["period"] = period;
  params["reference"] = l.absolute ? "absolute" : "command";
  params["start_time"] = start_time;
  params["start_phase"] = "cruise";
  for (const auto& kv : params) gen.params[kv.first.as<std::string>()] = setting(mc, kv.second, kv.first.as<std::string>());
  YAML::Node entry;
  entry["name"] = gen.name;
  entry["plugin"] = gen.plugin;
  entry["rate"] = *gen.rate;
  entry["params"] = params;
  gen.node = entry;
  mc.root["plugins"].push_back(entry);
  mc.plugins.push_back(std::move(gen));
}

struct Sample {
  double t, command, response;
};

/// One sample per tick once the generator publishes and the state is valid.
std::function<void(Nanos)> recorder(const Host& host, const TuneLoop& l, std::vector<Sample>& out) {
  // the topic names built once, not a heap string per tick
  return [&host, &l, &out, command_topic = std::string(kCommandTopic), state_topic = std::string("state")](Nanos now) {
    const OutputBase* c = host.topic_source(command_topic);
    const OutputBase* s = host.topic_source(state_topic);
    if (c == nullptr || s == nullptr || c->sequence() == 0 || s->sequence() == 0) return;
    if (c->type().name != msg::ControllerCommand::type_name || s->type().name != msg::State::type_name) return;
    const auto& cmd = *static_cast<const msg::ControllerCommand*>(c->data());
    const auto& st = *static_cast<const msg::State*>(s->data());
    if (!st.valid) return;
    const double v = command_of(l, cmd);
    out.push_back({to_seconds(now), v, response_of(l, st, v)});
  };
}

/// The step's figures; a response that did not move (y_f == y0: a loop that does not answer, or
/// a saturated one) has no rise, overshoot or settling (NaN, printed '-') instead of ending the
/// report.
StepMetrics metrics_or_flat(const std::vector<double>& t, const std::vector<double>& y, double r) {
  try {
    return step_metrics(t, y, r);
  } catch (const std::invalid_argument&) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {y.front(), y.back(), nan, nan, nan, r - y.back()};
  }
}

/// Edges: samples after the engagement where the command jumps by more than 3/4 of the
/// amplitude (the engagement itself is half a step and is not one; before it the follower's
/// own jumps, a new path segment, are not the signal's). Each step runs to the next edge; a step
/// shorter than 90 % of a half period (cut by the end of the flight) is not measured.
std::vector<TuneStep> measure(const std::vector<Sample>& x, double amplitude, double period, std::optional<double> engaged_s) {
  std::vector<std::size_t> edges;
  if (!engaged_s) return {};
  for (std::size_t i = 1; i < x.size(); ++i)
    if (x[i - 1].t >= *engaged_s && std::abs(x[i].command - x[i - 1].command) > 0.75 * std::abs(amplitude)) edges.push_back(i);
  std::vector<TuneStep> steps;
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const std::size_t a = edges[k], b = k + 1 < edges.size() ? edges[k + 1] : x.size();
    if (x[b - 1].t - x[a].t < 0.45 * period) continue;
    std::vector<double> t, y;
    for (std::size_t i = a; i < b; ++i) t.push_back(x[i].t), y.push_back(x[i].response);
    steps.push_back({x[a].t, x[a - 1].command, x[a].command, metrics_or_flat(t, y, x[a].command)});
  }
  return steps;
}

void write_csvs(const fs::path& dir, const TuneLoop& l, const std::vector<Sample>& x, const std::vector<TuneStep>& steps,
                std::optional<double> engaged_s) {
  std::string f = fmt::format("t [s],{} [{}],{} [{}]\n", l.symbol, l.unit, l.state, l.unit);
  for (const auto& s : x)
    if (engaged_s && s.t >= *engaged_s) f += fmt::format("{:.4f},{:.17g},{:.17g}\n", s.t, s.command, s.response);
  std::string g = "t [s],from,to,rise_time [s],overshoot [%],settling_time [s],steady_state_error,y0,y_final\n";
  for (const auto& s : steps)
    g += fmt::format("{:.4f},{:.17g},{:.17g},{:.6g},{:.6g},{:.6g},{:.6g},{:.17g},{:.17g}\n", s.t, s.from, s.to, s.m.rise_time,
                     s.m.overshoot_pct, s.m.settling_time, s.m.steady_state_error, s.m.y0, s.m.y_final);
  LogHealth health;
  if (!write_file_atomically(dir / "tune.csv", f, health) || !write_file_atomically(dir / "tune_steps.csv", g, health))
    std::fprintf(stderr, "tern: error: tune: %s (the table below is complete)\n", health.error().c_str());
}

/// Flight time the generator engaged (its summary's engaged_s), if it did.
std::optional<double> engagement(const Host& host) {
  for (const auto& inst : host.instances())
    if (inst->cfg.name == "signal")
      for (const auto& [k, v] : inst->plugin->summary())
        if (k == "engaged_s" && v >= 0.0) return v;
  return std::nullopt;
}

}  // namespace

const TuneLoop* find_tune_loop(std::string_view name) {
  for (const auto& l : kLoops)
    if (l.name == name) return &l;
  return nullptr;
}

std::string tune_loop_names() {
  std::string s;
  for (const auto& l : kLoops) s += (s.empty() ? "" : ", ") + std::string(l.name);
  return s;
}

TuneResult run_tune(const TuneOptions& o) {
  TuneResult r;
  r.loop = find_tune_loop(o.loop);
  if (r.loop == nullptr) throw ConfigError(fmt::format("unknown loop '{}': one of {}", o.loop, tune_loop_names()));
  r.amplitude = o.amplitude.value_or(r.loop->amplitude);
  r.period = o.period.value_or(r.loop->period);
  if (!std::isfinite(r.amplitude) || r.amplitude == 0.0)
    throw ConfigError(fmt::format("--amplitude {}: a step needs a finite, non-zero height ({})", r.amplitude, r.loop->unit));
  if (!(r.period >= 0.2 && r.period <= 3600.0)) throw ConfigError(fmt::format("--period {}: 0.2 .. 3600 s", r.period));
  r.duration = o.duration.value_or(60.0 + 2.5 * r.period);
  MissionConfig mc = load_config(o.config);
  apply_overrides(mc, o.overrides);
  insert_generator(mc, *r.loop, r.amplitude, r.period, o.start_time);
  mc.name += "-tune-" + std::string(r.loop->name);
  HostOptions opt;
  opt.seed = o.seed;
  opt.duration = r.duration;
  opt.log_dir = o.log_dir;
  opt.quiet = true;
  r.seed = o.seed.value_or(mc.seed);
  Host host(std::move(mc), opt);
  host.build();
  r.overrides = host.config().overrides;
  std::vector<Sample> x;
  host.add_tick_observer(recorder(host, *r.loop, x));
  r.flight = host.fly();
  r.engaged_s = engagement(host);
  r.steps = measure(x, r.amplitude, r.period, r.engaged_s);
  if (!r.flight.run_dir.empty()) write_csvs(r.flight.run_dir, *r.loop, x, r.steps, r.engaged_s);
  return r;
}

namespace {
std::string num(double v, const char* f) { return std::isfinite(v) ? fmt::format(fmt::runtime(f), v) : "-"; }
}  // namespace

std::string tune_report(const TuneResult& r, const std::string& config_name) {
  const TuneLoop& l = *r.loop;
  std::string s = fmt::format("tern tune {}: square wave on {}, {} {} peak to peak, period {} s; {}, seed {}, {} s\n", l.name, l.symbol,
                              r.amplitude, l.unit, r.period, config_name, r.seed, r.duration);
  if (!r.overrides.empty()) s += fmt::format("with {}\n", fmt::join(r.overrides, " "));
  s += r.engaged_s ? fmt::format("signal engaged at t = {:.2f} s; response: the estimated {}\n", *r.engaged_s, l.state)
                   : "signal never engaged (no cruise phase?)\n";
  s += fmt::format("{:>9} {:>10} {:>10} {:>9} {:>13} {:>13} {:>14}\n", "t [s]", "from", "to", "rise [s]", "overshoot [%]", "settling [s]",
                   fmt::format("ss error [{}]", l.unit));
  for (const auto& st : r.steps)
    s += fmt::format("{:>9.2f} {:>10.4f} {:>10.4f} {:>9} {:>13} {:>13} {:>14}\n", st.t, st.from, st.to, num(st.m.rise_time, "{:.3f}"),
                     num(st.m.overshoot_pct, "{:.1f}"), num(st.m.settling_time, "{:.2f}"), num(st.m.steady_state_error, "{:+.4f}"));
  s += fmt::format("rise 10-90 %, overshoot past the final value, settling into 2 % of the step, ss error = command - final value\n");
  s += fmt::format("(final value: the mean response over the last 10 % of the step; '-': never reached)\n");
  return s;
}

}  // namespace tern::core
