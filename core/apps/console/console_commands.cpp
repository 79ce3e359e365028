#include "console/console_commands.hpp"

#include <cmath>
#include <stdexcept>

#include "flight/host.hpp"

namespace tern::core {
namespace {

using nlohmann::json;

json to_json(const ParamValue& v) {
  return std::visit([](const auto& x) { return json(x); }, v);
}

/// A JSON value as a parameter value: the types ParamValue holds, nothing else.
ParamValue param_value(const json& v) {
  if (v.is_boolean()) return v.get<bool>();
  if (v.is_number_integer()) return v.get<std::int64_t>();
  if (v.is_number()) return v.get<double>();
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array()) {
    std::vector<double> out;
    for (const auto& e : v) {
      if (!e.is_number()) throw std::invalid_argument("a vector value holds numbers only");
      out.push_back(e.get<double>());
    }
    return out;
  }
  throw std::invalid_argument("value: a number, true/false, a string or an array of numbers");
}

double stick(const json& j, const char* name, double lo, double hi) {
  if (!j.contains(name) || !j[name].is_number()) throw std::invalid_argument(std::string("pilot: '") + name + "' must be a number");
  const double v = j[name].get<double>();
  if (!std::isfinite(v) || v < lo || v > hi)
    throw std::invalid_argument(std::string("pilot: '") + name + "' out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

json error(const std::string& message) { return {{"type", "error"}, {"message", message}}; }

/// The answer's text. A message may quote the request's bytes (the JSON parser's "last read:
/// '...'"), which need not be UTF-8 (a binary WebSocket frame): replaced by U+FFFD, where dump()'s
/// default would throw out of handle_request and out of the console's I/O thread.
std::string text_of(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

}  // namespace

json param_catalogue(const Host& host) {
  json out = json::array();
  for (const auto& [name, p] : host.parameters()) {
    const ParamSpec& s = p->spec();
    json e = {{"name", name},
              {"instance", name.substr(0, name.find('.'))},
              {"kind", param_kind_name(p->kind())},
              {"value", to_json(host.param_value(*p))},
              {"default", to_json(p->default_value())},
              {"unit", s.unit},
              {"choices", s.choices},
              {"size", s.size},
              {"live", s.live},
              {"description", s.description}};
    e["min"] = std::isfinite(s.min) ? json(s.min) : json(nullptr);
    e["max"] = std::isfinite(s.max) ? json(s.max) : json(nullptr);
    out.push_back(std::move(e));
  }
  return out;
}

msg::Rc pilot_from_json(const json& j) {
  msg::Rc rc;
  rc.roll = stick(j, "roll", -1.0, 1.0);
  rc.pitch = stick(j, "pitch", -1.0, 1.0);
  rc.yaw = stick(j, "yaw", -1.0, 1.0);
  rc.throttle = stick(j, "throttle", 0.0, 1.0);
  rc.rc_override = j.value("manual", false);
  rc.aux[0] = j.value("angle", false) ? 1.0 : -1.0;
  return rc;
}

std::string handle_request(Host& host, const std::string& text) {
  try {
    const json j = json::parse(text);
    const std::string type = j.is_object() ? j.value("type", "") : "";
    if (type == "param") {
      const std::string name = j.at("name").get<std::string>();
      const ParamValue v = param_value(j.at("value"));
      host.request_param(name, v, "console");
      return text_of(json{{"type", "param_ok"}, {"name", name}, {"value", to_json(v)}});
    }
    if (type == "pilot") {
      host.set_pilot(pilot_from_json(j));
      return "";
    }
    return text_of(error("unknown request type '" + type + "' (param, pilot)"));
  } catch (const std::exception& e) {  // bad JSON, a missing field, a refused value
    return text_of(error(e.what()));
  }
}

}  // namespace tern::core
