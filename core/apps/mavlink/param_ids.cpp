// core/apps/mavlink/param_ids.cpp: tern's parameter names as MAVLink ids (param_ids.hpp).
#include "mavlink/param_ids.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstdio>

#include "mavlink/mavlink_enums.hpp"
#include "tern/fnv1a.hpp"

namespace tern::core::mavlink {

std::string shorten_param_id(const std::string& qualified, int salt) {
  if (qualified.size() <= 16 && salt == 0) return qualified;
  Fnv1a f{Fnv1a::kOffsetBasis};
  f.chars(qualified);
  if (salt > 0) f.chars("#" + std::to_string(salt));
  const std::uint64_t h = f.h;
  const unsigned folded = static_cast<unsigned>((h ^ (h >> 16) ^ (h >> 32) ^ (h >> 48)) & 0xFFFFu);
  char hex[5];
  std::snprintf(hex, sizeof hex, "%04x", folded);
  return qualified.substr(0, 11) + "~" + hex;
}

ParamTable::ParamTable(const std::vector<std::pair<std::string, ParamKind>>& params) {
  for (const auto& [name, kind] : params) {
    std::uint8_t type = 0;
    switch (kind) {
      case ParamKind::real: type = MAV_PARAM_TYPE_REAL32; break;
      case ParamKind::integer: type = MAV_PARAM_TYPE_INT32; break;
      case ParamKind::boolean: type = MAV_PARAM_TYPE_UINT8; break;
      case ParamKind::text:
      case ParamKind::vector: continue;  // no MAVLink form
    }
    std::string id = shorten_param_id(name);
    for (int salt = 1; by_id_.count(id) != 0; ++salt) id = shorten_param_id(name, salt);
    by_id_[id] = params_.size();
    params_.push_back({id, name, kind, type});
  }
}

std::optional<std::size_t> ParamTable::find(const std::string& id) const {
  const auto it = by_id_.find(id.substr(0, 16));
  if (it == by_id_.end()) return std::nullopt;
  return it->second;
}

std::vector<std::pair<std::string, std::string>> ParamTable::shortened() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& p : params_)
    if (p.id != p.qualified) out.emplace_back(p.qualified, p.id);
  return out;
}

float to_mav_value(const tern::ParamValue& v) {
  if (const auto* d = std::get_if<double>(&v)) return static_cast<float>(*d);
  if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<float>(*i);
  if (const auto* b = std::get_if<bool>(&v)) return *b ? 1.0f : 0.0f;
  return std::nanf("");  // text and vector parameters are not in the table
}

tern::ParamValue from_mav_value(float v, ParamKind kind) {
  switch (kind) {
    case ParamKind::integer: return static_cast<std::int64_t>(std::llround(v));
    case ParamKind::boolean: return std::lround(v) != 0;
    default: {
      // the shortest decimal that reads back as this float ("0.7", not 0.699999988...): what the
      // GCS showed and its user typed
      char buf[32];
      const auto r = std::to_chars(buf, buf + sizeof buf, v);
      return std::strtod(std::string(buf, r.ptr).c_str(), nullptr);
    }
  }
}

}  // namespace tern::core::mavlink
