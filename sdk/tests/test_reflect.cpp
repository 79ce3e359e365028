#include <doctest/doctest.h>

#include "tern/msg/all.hpp"
#include "tern/port.hpp"

using namespace tern;

namespace v1 {
struct Sample {
  static constexpr std::string_view type_name = "test/Sample";
  Nanos stamp = 0;
  double a = 0;
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  template <class V>
  static constexpr void describe(V& v) {
    v(&Sample::stamp, "stamp", "ns");
    v(&Sample::a, "a", "m");
    v(&Sample::b, "b", "m/s", "n,e,d");
  }
};
}  // namespace v1
namespace v2 {  // same name, one field renamed
struct Sample {
  static constexpr std::string_view type_name = "test/Sample";
  Nanos stamp = 0;
  double a2 = 0;
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  template <class V>
  static constexpr void describe(V& v) {
    v(&Sample::stamp, "stamp", "ns");
    v(&Sample::a2, "a2", "m");
    v(&Sample::b, "b", "m/s", "n,e,d");
  }
};
}  // namespace v2
namespace v3 {  // same names, one field float instead of double
struct Sample {
  static constexpr std::string_view type_name = "test/Sample";
  Nanos stamp = 0;
  float a = 0;
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  template <class V>
  static constexpr void describe(V& v) {
    v(&Sample::stamp, "stamp", "ns");
    v(&Sample::a, "a", "m");
    v(&Sample::b, "b", "m/s", "n,e,d");
  }
};
}  // namespace v3

TEST_CASE("fingerprints change with any change of layout") {
  constexpr auto f1 = reflect::fingerprint<v1::Sample>();
  static_assert(f1 == reflect::fingerprint<v1::Sample>(), "fingerprint is a compile-time constant");
  CHECK(f1 != reflect::fingerprint<v2::Sample>());
  CHECK(f1 != reflect::fingerprint<v3::Sample>());
  CHECK(reflect::fingerprint<msg::Imu>() != reflect::fingerprint<msg::Mag>());
}

TEST_CASE("log columns name every component with its unit and offset") {
  const auto cols = reflect::layout<v1::Sample>();
  REQUIRE(cols.size() == 5);
  CHECK(cols[0].name == "stamp");
  CHECK(cols[0].kind == reflect::Scalar::i64);
  CHECK(cols[2].name == "b_n");
  CHECK(cols[4].name == "b_d");
  CHECK(cols[4].unit == "m/s");
  v1::Sample s;
  s.b = Eigen::Vector3d(1, 2, 3);
  double d;
  std::memcpy(&d, reinterpret_cast<const char*>(&s) + cols[4].offset, sizeof d);
  CHECK(d == 3.0);

  const auto state = reflect::layout<msg::State>();
  bool has_quat_w = false;
  msg::State st;
  st.quat = Eigen::Quaterniond(0.5, 0.1, 0.2, 0.3);
  for (const auto& c : state) {
    if (c.name == "quat_w") {
      has_quat_w = true;
      std::memcpy(&d, reinterpret_cast<const char*>(&st) + c.offset, sizeof d);
      CHECK(d == 0.5);
    }
  }
  CHECK(has_quat_w);
  // Nested arrays of structs are fingerprinted but not logged.
  const auto wl = reflect::layout<msg::WaypointList>();
  CHECK(wl.size() == 6);  // stamp, revision, count, loop, loops, immediate
}
