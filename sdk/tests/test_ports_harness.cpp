#include <doctest/doctest.h>

#include "tern/testing/harness.hpp"

using namespace tern;

namespace {
// A proportional controller: delta_a = -kp * phi, published only when the state updates.
class PTest final : public Plugin {
 public:
  void configure() override {
    declare(state_, "state", "estimated state");
    declare(actuators_, "actuators");
    declare(kp_, "kp", 1.0, ParamSpec("rad/rad", 0.0, 10.0, "roll gain"));
  }
  void step(Nanos now) override {
    if (!state_.updated()) return;
    msg::Actuators a;
    a.stamp = now;
    a.delta_a = -kp_() * state_->phi;
    actuators_.publish(a);
  }
  void reset() override { ++resets; }
  int resets = 0;

 private:
  Input<msg::State> state_;
  Output<msg::Actuators> actuators_;
  Param<double> kp_;
};
}  // namespace

TEST_CASE("harness: inputs, steps, outputs, parameters") {
  testing::Harness h(std::make_unique<PTest>(), {{"kp", 2.0}});
  msg::State s;
  s.phi = 0.1;
  h.set_input("state", s);
  h.step(from_seconds(0.01));
  CHECK(h.published("actuators") == 1);
  CHECK(h.output<msg::Actuators>("actuators").delta_a == doctest::Approx(-0.2));
  CHECK(h.output<msg::Actuators>("actuators").stamp == 10'000'000);
  // No new input: no new output.
  h.step(from_seconds(0.02));
  CHECK(h.published("actuators") == 1);
  h.set_param("kp", 1.0);
  h.set_input("state", s);
  h.step(from_seconds(0.03));
  CHECK(h.output<msg::Actuators>("actuators").delta_a == doctest::Approx(-0.1));
  CHECK_THROWS_AS(h.set_param("kp", 11.0), ParamError);
  CHECK_THROWS_AS(h.set_input("state", msg::Imu{}), std::logic_error);
  CHECK_THROWS_AS(h.output<msg::State>("actuators"), std::logic_error);
  CHECK_THROWS_AS(h.set_input("nope", s), std::logic_error);
}

TEST_CASE("harness: a configured value outside the range is refused at configure") {
  CHECK_THROWS_WITH_AS(testing::Harness(std::make_unique<PTest>(), {{"kp", -1.0}}),
                       "parameter 'test.kp': value -1 is outside the valid range [0, 10] rad/rad", ParamError);
  CHECK_THROWS_AS(testing::Harness(std::make_unique<PTest>(), {{"kq", 1.0}}), ParamError);
}

TEST_CASE("ports: an input reads its producer's latest value without copying") {
  Output<msg::Imu> out;
  Input<msg::Imu> in;
  CHECK_FALSE(in.has_value());
  CHECK(in.get().stamp == 0);
  in.bind(&out);
  CHECK_FALSE(in.updated());
  msg::Imu m;
  m.stamp = 5;
  out.publish(m);
  CHECK(in.updated());
  CHECK(&in.get() == &out.last());
  in.mark_seen();
  CHECK_FALSE(in.updated());
}
