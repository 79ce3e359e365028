// tern/param.hpp: typed plugin parameters with default, unit, valid range and description.
//
// A plugin declares each tunable as a member Param<T> (T: bool, std::int64_t, double,
// std::string or std::vector<double>) in configure(). Values come from the mission config or a
// parameter file, may change while flying (command line, DDS), and are always validated against
// the declared range: a bad value throws tern::ParamError naming the parameter, the value and
// the range, and leaves the old value in place. on_change callbacks run after a valid change.
// A parameter the plugin reads only when a flight starts (in start() or reset(): a file, a rate,
// an initial condition) is declared start_only(): the host refuses to change it in flight
// ("takes effect next flight") and applies a change asked for between flights before start().
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "tern/export.hpp"

namespace tern {

using ParamValue = std::variant<bool, std::int64_t, double, std::string, std::vector<double>>;

enum class ParamKind : std::uint8_t { boolean = 0, integer = 1, real = 2, text = 3, vector = 4 };

TERN_API const char* param_kind_name(ParamKind k);
/// Human-readable value, e.g. "0.5", "true", "[1, 2, 3]", "\"file.yaml\"".
TERN_API std::string to_string(const ParamValue& v);

/// A bad parameter value, name or type. what() is one line naming parameter, value and reason.
class TERN_API ParamError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  ~ParamError() override;
};

/// Unit, range and description of a parameter:
///   ParamSpec("rad/s", 0.0, 5.0, "roll-rate gain")
///   ParamSpec("", 0, 0, "aircraft file").as_path()
///   ParamSpec("", 0, 0, "turbulence").one_of({"none", "light", "moderate"})
///   ParamSpec("m/s", -50, 50, "steady wind NED").of_size(3)
///   ParamSpec("m", 0, 1000, "initial altitude").start_only()
struct ParamSpec {
  ParamSpec() = default;
  ParamSpec(std::string unit_, double min_, double max_, std::string description_)
      : unit(std::move(unit_)), min(min_), max(max_), description(std::move(description_)) {}
  ParamSpec& as_path() {
    is_path = true;
    return *this;
  }
  ParamSpec& one_of(std::vector<std::string> c) {
    choices = std::move(c);
    return *this;
  }
  ParamSpec& of_size(std::size_t n) {
    size = n;
    return *this;
  }
  ParamSpec& start_only() {
    live = false;
    return *this;
  }

  std::string unit;                                       ///< SI unit, "" if dimensionless
  double min = -std::numeric_limits<double>::infinity();  ///< inclusive (numbers, vector elements)
  double max = std::numeric_limits<double>::infinity();   ///< inclusive
  std::string description;                                ///< one line
  bool is_path = false;                                   ///< text value is a file path, resolved relative to the file that sets it
  std::vector<std::string> choices;                       ///< allowed text values (empty: any)
  std::size_t size = 0;                                   ///< required vector length (0: any)
  bool live = true;                                       ///< a change in flight takes effect at once (false: start_only())
};

class TERN_API ParamBase {
 public:
  virtual ~ParamBase();
  ParamBase(const ParamBase&) = delete;
  ParamBase& operator=(const ParamBase&) = delete;

  const std::string& name() const { return name_; }                 ///< e.g. "roll_kp"
  const std::string& qualified_name() const { return qualified_; }  ///< e.g. "slc.roll_kp"
  const ParamSpec& spec() const { return spec_; }
  ParamKind kind() const { return kind_; }
  virtual ParamValue value() const = 0;
  const ParamValue& default_value() const { return default_; }

  /// Validates and applies v (an integer is accepted for a real parameter, a whole real for an
  /// integer one). Throws ParamError (old value kept) when v has the wrong type or is out of range.
  void set(const ParamValue& v);
  /// Checks v without applying it; returns the converted value or throws ParamError.
  ParamValue validate(const ParamValue& v) const;

  // host/SDK side
  void set_identity(std::string name, std::string qualified, ParamSpec spec, ParamValue default_value);

 protected:
  ParamBase(ParamKind kind, ParamValue default_value) : kind_(kind), default_(std::move(default_value)) {}
  virtual void assign(const ParamValue& v) = 0;  ///< v already validated and converted

 private:
  ParamKind kind_;
  ParamValue default_;
  std::string name_, qualified_;
  ParamSpec spec_;
};

template <class T>
struct param_kind;
template <>
struct param_kind<bool> {
  static constexpr ParamKind value = ParamKind::boolean;
};
template <>
struct param_kind<std::int64_t> {
  static constexpr ParamKind value = ParamKind::integer;
};
template <>
struct param_kind<double> {
  static constexpr ParamKind value = ParamKind::real;
};
template <>
struct param_kind<std::string> {
  static constexpr ParamKind value = ParamKind::text;
};
template <>
struct param_kind<std::vector<double>> {
  static constexpr ParamKind value = ParamKind::vector;
};

template <class T>
class Param final : public ParamBase {
 public:
  Param() : ParamBase(param_kind<T>::value, T{}) {}
  const T& get() const { return value_; }
  const T& operator()() const { return value_; }
  operator const T&() const { return value_; }
  ParamValue value() const override { return value_; }
  /// Called after every valid change (not for the initial value).
  void on_change(std::function<void(const T&)> cb) { cb_ = std::move(cb); }

  // SDK side: initial value at declaration, without the callback.
  void init(const T& v) { value_ = v; }

 private:
  void assign(const ParamValue& v) override {
    value_ = std::get<T>(v);
    if (cb_) cb_(value_);
  }
  T value_{};
  std::function<void(const T&)> cb_;
};

}  // namespace tern
