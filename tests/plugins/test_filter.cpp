// test_filter: an estimator test plugin. Steps on `imu`; publishes `state` = truth, and counts
// steps in which the imu it reads was not published in the same tick (ordering check). Can be
// told to fail from a given time (fail_mode: segv, hang, exit; misbehave.hpp) and to log a line
// per second of flight (log_every_s), for the isolation and watchdog tests. With `origin` the state
// carries a valid origin (47.389 N, 8.034 E, 470 m: an aligned estimator with a GNSS fix), for what
// needs one (the ground station's mission protocol: fuzz_mission_protocol).
#include "misbehave.hpp"
#include "tern/plugin.hpp"
#include <spdlog/spdlog.h>

namespace {
class TestFilter final : public tern::Plugin {
 public:
  void configure() override {
    declare(imu_, "imu");
    declare(truth_, "truth", "", tern::Need::optional);
    declare(state_, "state");
    declare(edits_, "mission_edit", "counts runtime mission edits", tern::Need::optional);
    declare(valid_, "valid", false, tern::ParamSpec("", 0, 0, "publish the state as valid, status ok (an aligned estimator)"));
    declare(origin_, "origin", false, tern::ParamSpec("", 0, 0, "publish a valid origin (47.389 N, 8.034 E, 470 m MSL) with the state"));
    declare(fail_mode_, "fail_mode", "none", tern::ParamSpec("", 0, 0, "how to fail").one_of({"none", "segv", "hang", "exit"}));
    declare(fail_at_, "fail_at", 0.0, tern::ParamSpec("s", 0.0, 1e6, "flight time from which to fail"));
    declare(log_every_, "log_every_s", 0.0, tern::ParamSpec("s", 0.0, 1e6, "log one info line this often (0: never)"));
  }
  void step(tern::Nanos now) override {
    if (tern::to_seconds(now) >= fail_at_()) tern_test::misbehave(fail_mode_());
    if (log_every_() > 0 && now % tern::from_seconds(log_every_()) == 0) log().info("step at t={} ns", now);
    if (imu_->stamp != now) ++stale_;
    if (edits_.updated()) {
      ++edits_seen_;
      last_edit_id_ = edits_->id;
    }
    tern::msg::State s = truth_.get();
    s.stamp = now;
    s.p_n = imu_->accel.x();  // carries the seeded noise into the state log
    if (valid_()) {
      s.valid = true;
      s.status = tern::msg::StateStatus::ok;
    }
    if (origin_()) {
      s.origin_valid = true;
      s.origin_lat = 47.389, s.origin_lon = 8.034, s.origin_alt = 470.0;
    }
    state_.publish(s);
    ++steps_;
  }
  std::vector<std::pair<std::string, double>> summary() const override {
    return {{"stale_imu_steps", static_cast<double>(stale_)},
            {"steps", static_cast<double>(steps_)},
            {"mission_edits", static_cast<double>(edits_seen_)},
            {"last_edit_id", static_cast<double>(last_edit_id_)}};
  }

 private:
  tern::Input<tern::msg::Imu> imu_;
  tern::Input<tern::msg::State> truth_;
  tern::Output<tern::msg::State> state_;
  tern::Input<tern::msg::MissionEdit> edits_;
  tern::Param<bool> valid_, origin_;
  tern::Param<std::string> fail_mode_;
  tern::Param<double> fail_at_, log_every_;
  long stale_ = 0, steps_ = 0, edits_seen_ = 0, last_edit_id_ = 0;
};
}  // namespace

TERN_PLUGIN(TestFilter, "test_filter", tern::PluginKind::estimator, "host test: passes truth through on each imu sample")
