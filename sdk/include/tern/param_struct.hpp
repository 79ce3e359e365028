// tern/param_struct.hpp: a plugin's config struct declared as parameters once.
//
// The struct names its tunable fields in a static template member `describe`, the same idiom as
// the message structs (tern/reflect.hpp), with the parameter name and its ParamSpec:
//
//   struct LateralGains {
//     double roll_kp = 0.55;   ///< rad aileron / rad roll error
//     double roll_max = 0.7854;
//     template <class V> static void describe(V& v) {
//       v(&LateralGains::roll_kp, "roll_kp", ParamSpec("rad/rad", 0.0, 10.0, "roll -> aileron gain"));
//       v(&LateralGains::roll_max, "roll_max", ParamSpec("rad", 0.05, 1.4, "roll command limit"));
//     }
//   };
//
// and the plugin declares them all in configure() with `declare_struct(gains_)` (plugin.hpp):
// each figure has one name (the one in describe(), which the mission config and `--set` use),
// one default (the member initialiser), and the field always holds the parameter's value.
// A field describe() does not name is not a parameter. `v(&S::inner)` declares the fields of a
// described member struct with their own names; a field without a member pointer of its own (an
// array element) is named through a function: v([](S& s) -> double& { return s.t[1]; }, ...).
//
// Field types and their parameter kinds: bool (boolean), integral types (integer; the range
// must fit the field's type), float and double (real), std::string (text), std::vector<double>
// (vector), Eigen::Matrix<double, N, 1> (vector of size N).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "tern/param.hpp"

namespace tern::param_struct {

/// Parameter type that holds a field of type F, and the conversions between them.
template <class F, class = void>
struct Field {
  static_assert(sizeof(F) == 0, "tern::declare_struct: unsupported field type");
};
template <>
struct Field<bool> {
  using P = bool;
  static P to_param(bool f) { return f; }
  static bool from_param(P p) { return p; }
};
template <class F>
struct Field<F, std::enable_if_t<std::is_integral_v<F> && !std::is_same_v<F, bool>>> {
  using P = std::int64_t;
  static P to_param(F f) { return static_cast<P>(f); }
  static F from_param(P p) { return static_cast<F>(p); }
};
template <class F>
struct Field<F, std::enable_if_t<std::is_floating_point_v<F>>> {
  using P = double;
  static P to_param(F f) { return static_cast<P>(f); }
  static F from_param(P p) { return static_cast<F>(p); }
};
template <>
struct Field<std::string> {
  using P = std::string;
  static P to_param(const std::string& f) { return f; }
  static std::string from_param(const P& p) { return p; }
};
template <>
struct Field<std::vector<double>> {
  using P = std::vector<double>;
  static P to_param(const P& f) { return f; }
  static P from_param(const P& p) { return p; }
};
template <int N>
struct Field<Eigen::Matrix<double, N, 1>> {
  using P = std::vector<double>;
  using F = Eigen::Matrix<double, N, 1>;
  static P to_param(const F& f) { return P(f.data(), f.data() + N); }
  static F from_param(const P& p) { return Eigen::Map<const F>(p.data()); }
  static void adjust(ParamSpec& spec) { spec.of_size(N); }
};

template <class F, class = void>
struct has_adjust : std::false_type {};
template <class F>
struct has_adjust<F, std::void_t<decltype(Field<F>::adjust(std::declval<ParamSpec&>()))>> : std::true_type {};

/// Host of the parameters: takes ownership of a new parameter, declares it with its name,
/// default and spec (applying the configured value) and returns it.
using DeclareFn = std::function<ParamBase&(std::unique_ptr<ParamBase>, std::string, ParamValue, ParamSpec)>;

/// The visitor that S::describe() calls (Plugin::declare_struct makes one).
template <class S>
struct Binder {
  S& config;
  DeclareFn declare;
  std::shared_ptr<std::function<void()>> on_change;

  template <class F>
  void operator()(F S::*member, std::string name, ParamSpec spec) {
    bind<F>([member](S& s) -> F& { return s.*member; }, std::move(name), std::move(spec));
  }

  /// A field reached through a function of the struct (an array element, a member of a member):
  ///   v([](Config& c) -> double& { return c.timeout[1]; }, "gnss_timeout", ParamSpec(...));
  template <class Get, class = std::enable_if_t<std::is_invocable_v<Get&, S&>>>
  void operator()(Get get, std::string name, ParamSpec spec) {
    using F = std::remove_reference_t<std::invoke_result_t<Get&, S&>>;
    bind<F>(std::move(get), std::move(name), std::move(spec));
  }

  /// A described member struct: its fields are declared with their own names.
  template <class Inner>
  void operator()(Inner S::*member) {
    Binder<Inner> inner{config.*member, declare, on_change};
    Inner::describe(inner);
  }

 private:
  template <class F, class Get>
  void bind(Get get, std::string name, ParamSpec spec) {
    using Conv = Field<F>;
    using P = typename Conv::P;
    if constexpr (has_adjust<F>::value) Conv::adjust(spec);
    auto param = std::make_unique<Param<P>>();
    Param<P>& p = *param;
    const P def = Conv::to_param(get(config));
    p.init(def);
    declare(std::move(param), std::move(name), ParamValue(def), std::move(spec));
    get(config) = Conv::from_param(p.get());
    S* target = &config;
    auto cb = on_change;
    p.on_change([target, get, cb](const P& v) {
      get(*target) = Conv::from_param(v);
      if (*cb) (*cb)();
    });
  }
};

/// The parameter names a described struct declares, in order (for tests and documentation).
template <class S>
struct NameLister {
  std::vector<std::string>* names;
  template <class Field>
  void operator()(Field, std::string name, const ParamSpec&) {
    names->push_back(std::move(name));
  }
  template <class Inner>
  void operator()(Inner S::*) {
    NameLister<Inner> inner{names};
    Inner::describe(inner);
  }
};
template <class S>
std::vector<std::string> names() {
  std::vector<std::string> out;
  NameLister<S> v{&out};
  S::describe(v);
  return out;
}

}  // namespace tern::param_struct
