// core/apps/mavlink/component_metadata.cpp: general and parameter metadata JSON (component_metadata.hpp).
#include "mavlink/component_metadata.hpp"

#include <cmath>
#include <map>

#include <nlohmann/json.hpp>

namespace tern::core::mavlink {
namespace {

using nlohmann::json;

/// A number of the parameter's value, or nothing (text, vector, non-finite).
std::optional<double> number(const ParamValue& v) {
  if (const auto* b = std::get_if<bool>(&v)) return *b ? 1.0 : 0.0;
  if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  if (const auto* d = std::get_if<double>(&v); d && std::isfinite(*d)) return *d;
  return std::nullopt;
}

json describe(const MavParam& m, const ParamBase& p) {
  const ParamSpec& s = p.spec();
  json e = {{"name", m.id},
            {"type", m.kind == ParamKind::real ? "Float" : "Int32"},
            {"shortDesc", s.description},
            {"group", m.qualified.substr(0, m.qualified.find('.'))},
            {"rebootRequired", !s.live}};
  std::string long_desc = "tern parameter " + m.qualified;
  if (!s.live) long_desc += " (start-only: taken when a flight starts)";
  e["longDesc"] = long_desc;
  if (!s.unit.empty()) e["units"] = s.unit;
  if (m.kind == ParamKind::boolean) {
    e["min"] = 0;
    e["max"] = 1;
    e["values"] = json::array({{{"value", 0}, {"description", "false"}}, {{"value", 1}, {"description", "true"}}});
  } else {
    if (std::isfinite(s.min)) e["min"] = s.min;
    if (std::isfinite(s.max)) e["max"] = s.max;
  }
  if (const auto d = number(p.default_value())) e["default"] = *d;
  return e;
}

}  // namespace

MetadataFiles component_metadata(const ParamTable& table, const std::vector<std::pair<std::string, const ParamBase*>>& params) {
  std::map<std::string, const ParamBase*> by_name(params.begin(), params.end());
  json list = json::array();
  for (const MavParam& m : table.params())
    if (const auto p = by_name.find(m.qualified); p != by_name.end() && p->second) list.push_back(describe(m, *p->second));
  MetadataFiles out;
  out.parameters = json{{"version", 3}, {"parameters", list}}.dump();
  out.general = json{{"version", 1},
                     {"vendorName", "tern"},
                     {"modelName", "tern fixed-wing autopilot"},
                     {"metadataTypes",
                      json::array({{{"type", COMP_METADATA_TYPE_PARAMETER}, {"uri", std::string("mftp://") + kParameterMetadataFile}}})}}
                    .dump();
  return out;
}

}  // namespace tern::core::mavlink
