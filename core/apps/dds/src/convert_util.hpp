// core/apps/dds/src/convert_util.hpp: helpers of the tern <-> DDS conversions (the generated
// tern_msgs_convert.cpp, convert_rosplane.cpp, convert_ros.cpp).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "builtin_interfaces/msg/Time.h"
#include "dds_internal.hpp"
#include "std_msgs/msg/Header.h"
#include "tern/reflect.hpp"

namespace tern::core::ddsi {

/// "pkg::msg::dds_::Name_" -> "pkg/msg/Name" (convert.cpp).
std::string ros_type_name(const std::string& dds_type);

inline void to_time(builtin_interfaces::msg::Time& out, Nanos t) {
  const Nanos sec = t >= 0 ? t / 1000000000 : (t - 999999999) / 1000000000;
  out.sec(static_cast<std::int32_t>(sec));
  out.nanosec(static_cast<std::uint32_t>(t - sec * 1000000000));
}

inline void stamp(std_msgs::msg::Header& h, Nanos t) { to_time(h.stamp(), t); }

template <std::size_t N, class T, class V>
inline void vec(std::array<T, N>& out, const V& in) {
  for (std::size_t i = 0; i < N; ++i) out[i] = static_cast<T>(in[i]);
}

/// The reverse of vec: a wire array into a std::array or an Eigen vector of the same length.
template <class V, class T, std::size_t N>
inline void unvec(V& out, const std::array<T, N>& in) {
  for (std::size_t i = 0; i < N; ++i) out[static_cast<decltype(out.size())>(i)] = in[i];
}

/// "name: value" lines.
class Text {
 public:
  template <class T>
  Text& operator()(std::string_view name, const T& v) {
    if constexpr (std::is_same_v<T, bool>) {
      s_ += fmt::format("{}: {}\n", name, v ? "true" : "false");
    } else if constexpr (std::is_integral_v<T>) {
      s_ += fmt::format("{}: {}\n", name, static_cast<long long>(v));
    } else if constexpr (std::is_floating_point_v<T>) {
      s_ += fmt::format("{}: {}\n", name, v);
    } else if constexpr (std::is_same_v<T, std::string>) {
      s_ += fmt::format("{}: '{}'\n", name, v);
    } else {
      std::string items;
      for (const auto& x : v) items += (items.empty() ? "" : ", ") + fmt::format("{}", x);
      s_ += fmt::format("{}: [{}]\n", name, items);
    }
    return *this;
  }
  /// "name: 'sec.nanosec'"
  Text& time(std::string_view name, const builtin_interfaces::msg::Time& t) {
    return (*this)(name, fmt::format("{}.{:09d}", t.sec(), t.nanosec()));
  }
  /// A line made elsewhere (ending in a newline).
  Text& line(const std::string& text) {
    s_ += text;
    return *this;
  }
  Text& header(const std_msgs::msg::Header& h) {
    s_ += fmt::format("header.stamp: {}.{:09d}\nheader.frame_id: '{}'\n", h.stamp().sec(), h.stamp().nanosec(), h.frame_id());
    return *this;
  }
  std::string str() const { return s_; }

 private:
  std::string s_;
};

/// A type entry whose conversion writes one sample per message.
template <class M, class PS>
TypeEntry entry(std::function<void(const M&, typename PS::type&, Nanos epoch)> convert,
                std::function<std::string(const typename PS::type&)> render) {
  TypeEntry e;
  e.tern_type = M::type_name;
  e.fingerprint = reflect::fingerprint<M>();
  e.make_type = [] { return new Decoding<PS>(); };  // bytes Fast CDR refuses are dropped (decoding_type.hpp)
  e.make_sample = [] { return std::shared_ptr<void>(new typename PS::type(), [](void* p) { delete static_cast<typename PS::type*>(p); }); };
  e.convert = [convert](const void* m, void* s, Nanos epoch, const std::function<void()>& write) {
    convert(*static_cast<const M*>(m), *static_cast<typename PS::type*>(s), epoch);
    write();
  };
  e.render = [render](const void* s) { return render(*static_cast<const typename PS::type*>(s)); };
  e.dds_type = PS().getName();
  e.ros_type = ros_type_name(e.dds_type);
  return e;
}

/// Adds the rosflight_msgs and sensor_msgs conversions (convert_ros.cpp).
void add_ros_types(std::vector<TypeEntry>& v);

}  // namespace tern::core::ddsi
