#include "dispersion.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "config/config.hpp"
#include "counter_rng.hpp"
#include "config/error.hpp"

namespace tern::campaign {

using core::ConfigError;
using core::where;

namespace {

std::string field_of(const Dispersion& d) { return "dispersions." + d.target; }

bool numeric(const ParamBase& p) { return p.kind() == ParamKind::real || p.kind() == ParamKind::integer || p.kind() == ParamKind::vector; }

std::vector<double> nominal_numbers(const ParamBase& p) {
  const ParamValue v = p.value();
  if (const auto* d = std::get_if<double>(&v)) return {*d};
  if (const auto* i = std::get_if<std::int64_t>(&v)) return {static_cast<double>(*i)};
  if (const auto* x = std::get_if<std::vector<double>>(&v)) return *x;
  return {};
}

/// Components a numeric draw makes for p (its vector's size, else 1).
std::size_t components(const ParamBase& p) {
  if (p.kind() != ParamKind::vector) return 1;
  return p.spec().size ? p.spec().size : nominal_numbers(p).size();
}

/// The parameter value of drawn numbers x (fractions when relative), clamped to the range.
ParamValue to_value(const ParamBase& p, const std::vector<double>& x, bool relative) {
  const std::vector<double> nominal = nominal_numbers(p);
  std::vector<double> v(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    v[i] = relative ? nominal.at(i) * (1.0 + x[i]) : x[i];
    if (p.kind() == ParamKind::integer) v[i] = std::round(v[i]);
  }
  if (p.kind() == ParamKind::vector) return v;
  if (p.kind() == ParamKind::integer) return static_cast<std::int64_t>(v[0]);
  return v[0];
}

void check(const CampaignFile& c, const ParamBase& p, const ParamValue& v, const YAML::Node& at, const std::string& field) {
  try {
    p.validate(v);
  } catch (const ParamError& e) {
    throw ConfigError(where(c.file, at) + field + ": " + to_string(v) + " is not a valid " + p.qualified_name() + ": " + e.what());
  }
}

/// A choice/grid value as the parameter's value (relative: a fraction of the nominal).
ParamValue listed_value(const CampaignFile& c, const Resolved& r, std::size_t i) {
  const YAML::Node& n = r.d.values.at(i);
  const std::string field = fmt::format("{}.values[{}]", field_of(r.d), i);
  const ParamValue v = core::to_param_value(n, c.file, field);
  if (!r.d.relative) return v;
  if (const auto* d = std::get_if<double>(&v)) return to_value(*r.param, std::vector<double>(components(*r.param), *d), true);
  if (const auto* k = std::get_if<std::int64_t>(&v))
    return to_value(*r.param, std::vector<double>(components(*r.param), static_cast<double>(*k)), true);
  throw ConfigError(where(c.file, n) + field + ": a relative value must be a number, got '" + to_string(v) + "'");
}

/// Bound vector b fitted to n components (one value: every component).
std::vector<double> fit(const CampaignFile& c, const Resolved& r, const std::vector<double>& b, std::size_t n, const char* what) {
  if (b.size() == n) return b;
  if (b.size() == 1) return std::vector<double>(n, b[0]);
  throw ConfigError(where(c.file, r.d.node) + field_of(r.d) + fmt::format(".{}: {} values for {} component(s)", what, b.size(), n));
}

void check_instance(const CampaignFile& c, const Resolved& r) {
  const Dispersion& d = r.d;
  const ParamBase& p = *r.param;
  const std::string f = field_of(d);
  if (d.dist == Dist::choice || d.dist == Dist::grid) {
    for (std::size_t i = 0; i < d.values.size(); ++i) check(c, p, listed_value(c, r, i), d.values[i], fmt::format("{}.values[{}]", f, i));
    return;
  }
  if (!numeric(p))
    throw ConfigError(where(c.file, d.node) + f + ": " + p.qualified_name() + " is a " + param_kind_name(p.kind()) +
                      " parameter: use choice or grid");
  const std::size_t n = components(p);
  if (d.dist == Dist::uniform) {
    check(c, p, to_value(p, fit(c, r, d.low, n, "low"), d.relative), d.node["low"], f + ".low");
    check(c, p, to_value(p, fit(c, r, d.high, n, "high"), d.relative), d.node["high"], f + ".high");
  } else if (d.dist == Dist::normal) {
    check(c, p, to_value(p, fit(c, r, d.mean, n, "mean"), d.relative), d.node["mean"], f + ".mean");
    fit(c, r, d.sd, n, "sd");
    if (d.clip) {
      check(c, p, to_value(p, std::vector<double>(n, d.clip->first), d.relative), d.node["clip"], f + ".clip");
      check(c, p, to_value(p, std::vector<double>(n, d.clip->second), d.relative), d.node["clip"], f + ".clip");
    }
  } else if (d.dist == Dist::polar) {
    if (p.kind() != ParamKind::vector || (n != 2 && n != 3))
      throw ConfigError(where(c.file, d.node) + f + ": polar needs a vector parameter of 2 or 3 components; " + p.qualified_name() +
                        " is not");
    const double s = d.speed.second;
    const std::vector<std::vector<double>> extremes = {{s, 0, 0}, {-s, 0, 0}, {0, s, 0}, {0, -s, 0}};
    for (const auto& v : extremes)
      check(c, p, std::vector<double>(v.begin(), v.begin() + static_cast<long>(n)), d.node["speed"], f + ".speed");
    if (r.into_wind) {
      check(c, *r.into_wind, -M_PI, d.node["into_wind"], f + ".into_wind");
      check(c, *r.into_wind, M_PI, d.node["into_wind"], f + ".into_wind");
    }
  }
}

const ParamBase* find_param(const CampaignFile& c, const ParamCatalogue& params, const std::string& name, const YAML::Node& at,
                            const std::string& field) {
  const auto it = params.find(name);
  if (it != params.end()) return it->second;
  std::vector<std::string> names;
  for (const auto& kv : params) names.push_back(kv.first);
  throw ConfigError(where(c.file, at) + field + ": the base mission has no parameter '" + name + "'" + core::did_you_mean(name, names) +
                    " (tern params " + c.base.string() + " lists them)");
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::size_t a = 0;
  for (std::size_t b; (b = s.find('.', a)) != std::string::npos; a = b + 1) out.push_back(s.substr(a, b - a));
  out.push_back(s.substr(a));
  return out;
}

std::string join(const std::vector<std::string>& parts) { return fmt::format("{}", fmt::join(parts, ".")); }

bool is_number(const YAML::Node& n) {
  if (!n.IsScalar()) return false;
  try {
    return std::isfinite(n.as<double>());
  } catch (const YAML::Exception&) {
    return false;
  }
}

/// The drawn fractions' extremes must keep 1 + v > 0 (a sign flip is not a perturbation).
void check_aircraft(const CampaignFile& c, const Dispersion& d) {
  std::vector<double> lows;
  if (d.dist == Dist::uniform) lows = d.low;
  if (d.dist == Dist::normal) lows = {d.clip ? d.clip->first : -1.0};
  if (d.dist == Dist::choice || d.dist == Dist::grid)
    for (std::size_t i = 0; i < d.values.size(); ++i) {
      if (!is_number(d.values[i]))
        throw ConfigError(where(c.file, d.values[i]) + field_of(d) + fmt::format(".values[{}]: expected a number (a fraction)", i));
      lows.push_back(d.values[i].as<double>());
    }
  for (double v : lows)
    if (!(v > -1.0))
      throw ConfigError(where(c.file, d.node) + field_of(d) +
                        fmt::format(": relative value {} would make the number <= 0 x nominal (must be > -1{})", v,
                                    d.dist == Dist::normal ? "; give a clip" : ""));
}

void resolve_aircraft(const CampaignFile& c, const Dispersion& d, const YAML::Node& aircraft, std::vector<Resolved>& out) {
  const std::string f = field_of(d);
  if (!aircraft || aircraft.IsNull()) throw ConfigError(where(c.file, d.node) + f + ": the base mission names no aircraft:");
  check_aircraft(c, d);
  std::vector<std::string> path = split(d.target.substr(9));
  const bool all = path.back() == "*";
  if (all) path.pop_back();
  YAML::Node n = YAML::Clone(aircraft);
  for (const auto& k : path) {
    if (!n.IsMap() || !n[k])
      throw ConfigError(where(c.file, d.node) + f + ": the aircraft file has no '" + join(path) + "' (at '" + k + "')");
    n = n[k];
  }
  auto add = [&](const std::vector<std::string>& p, const YAML::Node& v) {
    Resolved r;
    r.d = d;
    r.d.target = "aircraft." + join(p);
    r.aircraft_path = p;
    r.aircraft_nominal = v.as<double>();
    out.push_back(r);
  };
  if (!all) {
    if (!is_number(n)) throw ConfigError(where(c.file, d.node) + f + ": aircraft '" + join(path) + "' is not a number");
    add(path, n);
    return;
  }
  if (!n.IsMap()) throw ConfigError(where(c.file, d.node) + f + ": aircraft '" + join(path) + "' is not a map");
  for (const auto& kv : n) {
    if (!is_number(kv.second)) continue;  // e.g. stall_blend: false
    std::vector<std::string> p = path;
    p.push_back(kv.first.Scalar());
    add(p, kv.second);
  }
}

double wrap_pi(double a) {
  a = std::fmod(a + M_PI, 2 * M_PI);
  if (a <= 0) a += 2 * M_PI;
  return a - M_PI;
}

}  // namespace

std::string number_text(double v) { return fmt::format("{}", v); }

std::vector<Resolved> resolve_dispersions(const CampaignFile& c, const ParamCatalogue& params, const YAML::Node& aircraft) {
  std::vector<Resolved> out;
  for (const auto& d : c.dispersions) {
    if (d.aircraft()) {
      resolve_aircraft(c, d, aircraft, out);
      continue;
    }
    Resolved r;
    r.d = d;
    r.param = find_param(c, params, d.target, d.node, field_of(d));
    if (d.into_wind) r.into_wind = find_param(c, params, *d.into_wind, d.node["into_wind"], field_of(d) + ".into_wind");
    check_instance(c, r);
    out.push_back(r);
  }
  return out;
}

namespace {

/// The fractions or values a numeric uniform/normal draws for flight k, one per component.
std::vector<double> draw_numbers(const CampaignFile& c, const Resolved& r, std::size_t n, std::size_t k) {
  const std::uint64_t s = stream_id(r.d.target);
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (r.d.dist == Dist::uniform) {
      const double lo = r.d.low.size() == 1 ? r.d.low[0] : r.d.low[i], hi = r.d.high.size() == 1 ? r.d.high[0] : r.d.high[i];
      x[i] = lo + (hi - lo) * draw_uniform(c.seed, k, s, i);
    } else {
      const double m = r.d.mean.size() == 1 ? r.d.mean[0] : r.d.mean[i], sd = r.d.sd.size() == 1 ? r.d.sd[0] : r.d.sd[i];
      x[i] = m + sd * draw_normal(c.seed, k, s, i);
      if (r.d.clip) x[i] = std::clamp(x[i], r.d.clip->first, r.d.clip->second);
      if (!r.d.relative && r.param) x[i] = std::clamp(x[i], r.param->spec().min, r.param->spec().max);
    }
  }
  return x;
}

std::size_t choose(const CampaignFile& c, const Resolved& r, std::size_t k) {
  const double u = draw_uniform(c.seed, k, stream_id(r.d.target));
  if (r.d.weights.empty()) return std::min(r.d.values.size() - 1, static_cast<std::size_t>(u * static_cast<double>(r.d.values.size())));
  double total = 0;
  for (double w : r.d.weights) total += w;
  double acc = 0;
  for (std::size_t i = 0; i < r.d.weights.size(); ++i) {
    acc += r.d.weights[i] / total;
    if (u < acc) return i;
  }
  return r.d.weights.size() - 1;
}

void add_numeric(FlightDraw& f, const Resolved& r, const std::vector<double>& x) {
  const std::string unit = r.d.relative ? "rel" : r.param ? r.param->spec().unit : "";
  for (std::size_t i = 0; i < x.size(); ++i) {
    double shown = x[i];
    if (!r.d.relative && r.param && r.param->kind() == ParamKind::integer) shown = std::round(shown);
    f.columns.push_back({x.size() == 1 ? r.d.target : fmt::format("{}[{}]", r.d.target, i), unit, number_text(shown), shown});
  }
}

void draw_polar(const CampaignFile& c, const Resolved& r, std::size_t k, FlightDraw& f) {
  const double speed = r.d.speed.first + (r.d.speed.second - r.d.speed.first) * draw_uniform(c.seed, k, stream_id(r.d.target + ".speed"));
  const double from =
      r.d.from_deg.first + (r.d.from_deg.second - r.d.from_deg.first) * draw_uniform(c.seed, k, stream_id(r.d.target + ".from_deg"));
  const double chi = from * M_PI / 180.0;
  std::vector<double> v = {-speed * std::cos(chi), -speed * std::sin(chi), 0.0};  // blowing to the opposite of `from`
  v.resize(components(*r.param));
  f.params[r.d.target] = v;
  f.columns.push_back({r.d.target + ".speed", r.param->spec().unit, number_text(speed), speed});
  f.columns.push_back({r.d.target + ".from_deg", "deg", number_text(from), from});
  if (r.into_wind) f.params[r.into_wind->qualified_name()] = wrap_pi(chi);
}

}  // namespace

FlightDraw draw_flight(const CampaignFile& c, const std::vector<Resolved>& dispersions, std::size_t k) {
  FlightDraw f;
  f.index = k;
  f.seed = flight_seed(c.seed, k);
  // grid coordinates: k walks the grid's points in order, the last grid dispersion fastest
  std::vector<std::size_t> grid_at(dispersions.size(), 0);
  std::size_t g = k % c.grid_points;
  for (std::size_t i = dispersions.size(); i-- > 0;) {
    if (dispersions[i].d.dist != Dist::grid) continue;
    grid_at[i] = g % dispersions[i].d.values.size();
    g /= dispersions[i].d.values.size();
  }
  for (std::size_t i = 0; i < dispersions.size(); ++i) {
    const Resolved& r = dispersions[i];
    if (r.d.dist == Dist::polar) {
      draw_polar(c, r, k, f);
    } else if (r.d.dist == Dist::choice || r.d.dist == Dist::grid) {
      const std::size_t j = r.d.dist == Dist::grid ? grid_at[i] : choose(c, r, k);
      const YAML::Node& n = r.d.values[j];
      if (r.param) {
        f.params[r.d.target] = listed_value(c, r, j);
        const bool num = is_number(n);
        f.columns.push_back({r.d.target, r.d.relative ? "rel" : r.param->spec().unit,
                             n.IsScalar() ? n.Scalar() : to_string(core::to_param_value(n, c.file, "")), num ? n.as<double>() : NAN});
      } else {
        const double x = n.as<double>();
        f.aircraft[join(r.aircraft_path)] = r.aircraft_nominal * (1.0 + x);
        f.columns.push_back({r.d.target, "rel", number_text(x), x});
      }
    } else if (r.param) {
      const std::vector<double> x = draw_numbers(c, r, components(*r.param), k);
      f.params[r.d.target] = to_value(*r.param, x, r.d.relative);
      add_numeric(f, r, x);
    } else {
      const double x = draw_numbers(c, r, 1, k)[0];
      f.aircraft[join(r.aircraft_path)] = r.aircraft_nominal * (1.0 + x);
      add_numeric(f, r, {x});
    }
  }
  return f;
}

}  // namespace tern::campaign
