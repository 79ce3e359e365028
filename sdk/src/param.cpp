#include "tern/param.hpp"

#include <cmath>
#include <sstream>

#include <fmt/format.h>

namespace tern {

ParamError::~ParamError() = default;
ParamBase::~ParamBase() = default;

const char* param_kind_name(ParamKind k) {
  switch (k) {
    case ParamKind::boolean: return "bool";
    case ParamKind::integer: return "integer";
    case ParamKind::real: return "number";
    case ParamKind::text: return "string";
    case ParamKind::vector: return "list of numbers";
  }
  return "?";
}

namespace {
std::string num(double x) { return fmt::format("{}", x); }
}  // namespace

std::string to_string(const ParamValue& v) {
  struct V {
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(std::int64_t i) const { return std::to_string(i); }
    std::string operator()(double d) const { return num(d); }
    std::string operator()(const std::string& s) const { return "\"" + s + "\""; }
    std::string operator()(const std::vector<double>& v) const {
      std::string out = "[";
      for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + num(v[i]);
      return out + "]";
    }
  };
  return std::visit(V{}, v);
}

static ParamKind kind_of(const ParamValue& v) { return static_cast<ParamKind>(v.index()); }

void ParamBase::set_identity(std::string name, std::string qualified, ParamSpec spec, ParamValue default_value) {
  name_ = std::move(name);
  qualified_ = std::move(qualified);
  spec_ = std::move(spec);
  default_ = std::move(default_value);
}

ParamValue ParamBase::validate(const ParamValue& v_in) const {
  ParamValue v = v_in;
  const ParamKind got = kind_of(v);
  auto fail = [&](const std::string& why) -> ParamError {
    return ParamError(fmt::format("parameter '{}': value {} {}", qualified_, to_string(v_in), why));
  };
  if (got != kind_) {
    if (kind_ == ParamKind::real && got == ParamKind::integer) {
      v = static_cast<double>(std::get<std::int64_t>(v));
    } else if (kind_ == ParamKind::integer && got == ParamKind::real && std::get<double>(v) == std::floor(std::get<double>(v)) &&
               std::fabs(std::get<double>(v)) < 9.0e15) {
      v = static_cast<std::int64_t>(std::get<double>(v));
    } else if (kind_ == ParamKind::vector && (got == ParamKind::real || got == ParamKind::integer)) {
      throw fail(fmt::format("is a single number; expected a {}", param_kind_name(kind_)));
    } else {
      throw fail(fmt::format("has the wrong type: expected a {}, got a {}", param_kind_name(kind_), param_kind_name(got)));
    }
  }
  auto range = [&]() {
    return fmt::format("outside the valid range [{}, {}]{}", num(spec_.min), num(spec_.max), spec_.unit.empty() ? "" : " " + spec_.unit);
  };
  auto check = [&](double x) {
    if (std::isnan(x)) throw fail("is not a number");
    if (x < spec_.min || x > spec_.max) throw fail("is " + range());
  };
  switch (kind_) {
    case ParamKind::integer: check(static_cast<double>(std::get<std::int64_t>(v))); break;
    case ParamKind::real: check(std::get<double>(v)); break;
    case ParamKind::vector: {
      const auto& vec = std::get<std::vector<double>>(v);
      if (spec_.size != 0 && vec.size() != spec_.size) throw fail(fmt::format("has {} elements; expected {}", vec.size(), spec_.size));
      for (double x : vec) check(x);
      break;
    }
    case ParamKind::text:
      if (!spec_.choices.empty()) {
        const auto& s = std::get<std::string>(v);
        bool ok = false;
        for (const auto& c : spec_.choices) ok = ok || c == s;
        if (!ok) throw fail(fmt::format("is not one of {}", fmt::join(spec_.choices, ", ")));
      }
      break;
    case ParamKind::boolean: break;
  }
  return v;
}

void ParamBase::set(const ParamValue& v) { assign(validate(v)); }

}  // namespace tern
