// Plugin::declare_struct: a described config struct declared as parameters once.
#include <doctest/doctest.h>

#include <array>
#include <memory>

#include "tern/plugin.hpp"
#include "tern/testing/harness.hpp"

using namespace tern;

namespace {

struct Limits {
  double theta_max = 0.35;
  template <class V>
  static void describe(V& v) {
    v(&Limits::theta_max, "theta_max", ParamSpec("rad", 0.0, 1.2, "pitch command upper limit"));
  }
};

struct Gains {
  double kp = 0.55;
  std::int64_t aux = -1;
  int count = 3;
  bool hold = true;
  std::string mode = "passthrough";
  Eigen::Vector3d offset = Eigen::Vector3d(1.0, 2.0, 3.0);
  Limits limits;
  double not_a_parameter = 7.0;
  std::array<double, 2> timeout{0.5, 1.0};
  template <class V>
  static void describe(V& v) {
    v(&Gains::kp, "roll_kp", ParamSpec("rad/rad", 0.0, 10.0, "roll -> aileron gain"));
    v(&Gains::aux, "aux", ParamSpec("", -1, 3, "aux channel"));
    v(&Gains::count, "count", ParamSpec("", 1, 10, "a count"));
    v(&Gains::hold, "hold", ParamSpec("", 0, 0, "course hold"));
    v(&Gains::mode, "mode", ParamSpec("", 0, 0, "manual mode").one_of({"passthrough", "angle"}));
    v(&Gains::offset, "offset", ParamSpec("m", -10, 10, "antenna offset"));
    v(&Gains::limits);
    v([](Gains& g) -> double& { return g.timeout[1]; }, "gnss_timeout", ParamSpec("s", 0.001, 60.0, "GNSS time-out"));
  }
};

class StructPlugin final : public Plugin {
 public:
  void configure() override {
    declare_struct(gains_, [this] { ++changes_; });
  }
  void step(Nanos) override {}
  Gains gains_;
  int changes_ = 0;
};

}  // namespace

TEST_CASE("declare_struct declares every described field with the member initialiser as default") {
  auto plugin = std::make_unique<StructPlugin>();
  auto* p = plugin.get();
  testing::Harness h(std::move(plugin));
  CHECK(param_struct::names<Gains>() ==
        std::vector<std::string>{"roll_kp", "aux", "count", "hold", "mode", "offset", "theta_max", "gnss_timeout"});
  REQUIRE(p->params().size() == 8);
  CHECK(std::get<double>(p->find_param("gnss_timeout")->default_value()) == 1.0);
  const ParamBase* kp = p->find_param("roll_kp");
  REQUIRE(kp != nullptr);
  CHECK(std::get<double>(kp->default_value()) == 0.55);
  CHECK(kp->spec().unit == "rad/rad");
  CHECK(kp->spec().max == 10.0);
  CHECK(kp->spec().description == "roll -> aileron gain");
  CHECK(kp->kind() == ParamKind::real);
  CHECK(p->find_param("count")->kind() == ParamKind::integer);
  CHECK(p->find_param("hold")->kind() == ParamKind::boolean);
  CHECK(p->find_param("mode")->spec().choices.size() == 2);
  CHECK(p->find_param("offset")->spec().size == 3);  // from the Eigen vector's size
  CHECK(std::get<std::vector<double>>(p->find_param("offset")->default_value()) == std::vector<double>{1, 2, 3});
  CHECK(std::get<double>(p->find_param("theta_max")->default_value()) == 0.35);
  CHECK(p->find_param("not_a_parameter") == nullptr);
  CHECK(p->changes_ == 0);
}

TEST_CASE("declare_struct applies configured values and keeps the struct updated on changes") {
  auto plugin = std::make_unique<StructPlugin>();
  auto* p = plugin.get();
  testing::Harness h(std::move(plugin), {{"roll_kp", 1.5}, {"mode", std::string("angle")}, {"count", std::int64_t{5}}});
  CHECK(p->gains_.kp == 1.5);
  CHECK(p->gains_.mode == "angle");
  CHECK(p->gains_.count == 5);
  CHECK(p->changes_ == 0);  // configured values are not changes

  h.set_param("roll_kp", 2.5);
  CHECK(p->gains_.kp == 2.5);
  h.set_param("theta_max", 0.5);
  CHECK(p->gains_.limits.theta_max == 0.5);
  h.set_param("offset", std::vector<double>{4, 5, 6});
  CHECK(p->gains_.offset.z() == 6.0);
  h.set_param("hold", false);
  CHECK_FALSE(p->gains_.hold);
  h.set_param("gnss_timeout", 2.0);
  CHECK(p->gains_.timeout[1] == 2.0);
  CHECK(p->gains_.timeout[0] == 0.5);
  CHECK(p->changes_ == 5);

  CHECK_THROWS_AS(h.set_param("roll_kp", 11.0), ParamError);  // out of range: struct unchanged
  CHECK(p->gains_.kp == 2.5);
  CHECK_THROWS_AS(h.set_param("offset", std::vector<double>{1, 2}), ParamError);
  CHECK(p->changes_ == 5);
}

TEST_CASE("declare_struct refuses an invalid configured value with the parameter's name") {
  CHECK_THROWS_WITH_AS(testing::Harness(std::make_unique<StructPlugin>(), {{"roll_kp", 20.0}}), doctest::Contains("roll_kp"), ParamError);
}
