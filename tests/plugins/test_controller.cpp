// test_controller: a controller test plugin. Throttle = 0.5 + kp (h_target - h), saturated;
// delta_e = the `tag` parameter so tests can see which controller is flying, delta_a = `aileron`.
// Can be told to fail (throw, write NaN, or stop publishing: silent; or segv, hang, exit, see
// misbehave.hpp) from a given time, to exercise the phase router's fallback, its safety monitor,
// isolation and the watchdog.
#include <cmath>
#include <stdexcept>

#include "tern/math.hpp"
#include "misbehave.hpp"
#include "tern/plugin.hpp"

#ifndef TERN_TEST_VERSION
#define TERN_TEST_VERSION 1
#endif

namespace {
class TestController final : public tern::Plugin {
 public:
  void configure() override {
    declare(state_, "state");
    declare(phase_, "flight_phase", "", tern::Need::optional);
    declare(actuators_, "actuators");
    declare(internals_, "controller_internals");
    declare(h_target_, "h_target", 30.0, tern::ParamSpec("m", -100.0, 10000.0, "altitude to hold"));
    declare(kp_, "kp", 0.05, tern::ParamSpec("1/m", 0.0, 10.0, "throttle per metre of altitude error"));
    declare(tag_, "tag", 0.0, tern::ParamSpec("rad", -1.0, 1.0, "constant elevator command identifying this controller"));
    declare(aileron_, "aileron", 0.0, tern::ParamSpec("rad", -1.0, 1.0, "constant aileron command"));
    declare(fail_mode_, "fail_mode", "none",
            tern::ParamSpec("", 0, 0, "how to fail").one_of({"none", "throw", "nan", "silent", "segv", "hang", "exit"}));
    declare(fail_at_, "fail_at", 0.0, tern::ParamSpec("s", 0.0, 1e6, "flight time from which to fail"));
  }
  void step(tern::Nanos now) override {
    if (fail_mode_() != "none" && tern::to_seconds(now) >= fail_at_()) {
      if (fail_mode_() == "throw") throw std::runtime_error("deliberate failure");
      if (fail_mode_() == "silent") return;
      tern_test::misbehave(fail_mode_());
    }
    tern::msg::Actuators a;
    a.stamp = now;
    a.delta_t = tern::saturate(0.5 + kp_() * (h_target_() - (-state_->p_d)), 0.0, 1.0);
    a.delta_e = tag_();
    a.delta_a = aileron_();
    if (fail_mode_() == "nan" && tern::to_seconds(now) >= fail_at_()) a.delta_e = std::nan("");
    actuators_.publish(a);
    tern::msg::ControllerInternals ci;
    ci.stamp = now;
    ci.delta_t_c = a.delta_t;
    ci.alt_zone = static_cast<std::uint8_t>(phase_->phase);
    internals_.publish(ci);
  }
  void take_over(const tern::msg::Actuators& last) override {
    ++take_overs_;
    last_take_over_delta_t_ = last.delta_t;
  }
  std::vector<std::pair<std::string, double>> summary() const override {
    return {{"take_overs", static_cast<double>(take_overs_)},
            {"last_take_over_delta_t", last_take_over_delta_t_},
            {"version", TERN_TEST_VERSION}};
  }

 private:
  tern::Input<tern::msg::State> state_;
  tern::Input<tern::msg::FlightPhase> phase_;
  tern::Output<tern::msg::Actuators> actuators_;
  tern::Output<tern::msg::ControllerInternals> internals_;
  tern::Param<double> h_target_, kp_, tag_, aileron_, fail_at_;
  tern::Param<std::string> fail_mode_;
  int take_overs_ = 0;
  double last_take_over_delta_t_ = -1;
};
}  // namespace

TERN_PLUGIN(TestController, "test_controller", tern::PluginKind::controller, "host test: throttle-only altitude hold")
