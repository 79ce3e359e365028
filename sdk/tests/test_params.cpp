#include <doctest/doctest.h>

#include "tern/param.hpp"

using namespace tern;

TEST_CASE("parameters validate type and range and keep the old value on error") {
  Param<double> kp;
  kp.init(0.5);
  kp.set_identity("roll_kp", "slc.roll_kp", ParamSpec("", 0.0, 5.0, "roll proportional gain"), 0.5);
  int calls = 0;
  double seen = 0;
  kp.on_change([&](const double& v) {
    ++calls;
    seen = v;
  });
  kp.set(std::int64_t{2});  // integers are accepted for real parameters
  CHECK(kp() == 2.0);
  CHECK(calls == 1);
  CHECK(seen == 2.0);
  CHECK_THROWS_WITH_AS(kp.set(7.5), "parameter 'slc.roll_kp': value 7.5 is outside the valid range [0, 5]", ParamError);
  CHECK(kp() == 2.0);
  CHECK_THROWS_WITH_AS(kp.set(std::string("fast")),
                       "parameter 'slc.roll_kp': value \"fast\" has the wrong type: expected a number, got a string", ParamError);
  CHECK(calls == 1);

  Param<std::int64_t> n;
  n.set_identity("n", "x.n", ParamSpec("", 1, 10, ""), std::int64_t{1});
  CHECK_THROWS_AS(n.set(2.5), ParamError);
  n.set(3.0);
  CHECK(n() == 3);

  Param<std::vector<double>> wind;
  wind.set_identity("wind", "sim.wind", ParamSpec("m/s", -50, 50, "").of_size(3), std::vector<double>{0, 0, 0});
  CHECK_THROWS_WITH(wind.set(std::vector<double>{1, 2}), "parameter 'sim.wind': value [1, 2] has 2 elements; expected 3");
  wind.set(std::vector<double>{1, 2, 3});
  CHECK(wind().at(2) == 3.0);

  Param<std::string> mode;
  mode.set_identity("mode", "x.mode", ParamSpec("", 0, 0, "").one_of({"light", "moderate"}), std::string("light"));
  CHECK_THROWS_WITH(mode.set(std::string("severe")), "parameter 'x.mode': value \"severe\" is not one of light, moderate");
}
