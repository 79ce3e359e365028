// test_sensor: an I/O test plugin for the host's tests. A point "aircraft" whose altitude rate is
// climb_gain * (delta_t - 0.5); publishes `truth` (State) and a seeded-noise `imu` every step.
#include <random>

#include "tern/math.hpp"

#include "tern/plugin.hpp"

namespace {
class TestSensor final : public tern::Plugin {
 public:
  void configure() override {
    declare(actuators_, "actuators", "throttle drives the climb rate", tern::Need::optional);
    declare(imu_, "imu", "noise on accel");
    declare(truth_, "truth", "altitude state");
    declare(climb_gain_, "climb_gain", 10.0, tern::ParamSpec("m/s", 0.0, 100.0, "climb rate per unit of throttle above 0.5"));
    declare(noise_, "noise", 0.1, tern::ParamSpec("m/s^2", 0.0, 10.0, "accelerometer noise (uniform half-width)"));
    declare(h0_, "h0", 0.0, tern::ParamSpec("m", -100.0, 10000.0, "initial altitude").start_only());
  }
  void start() override {
    rng_.seed(context().seed());
    h_ = h0_();
    last_ = -1;
  }
  void step(tern::Nanos now) override {
    const double dt = last_ < 0 ? 0.0 : tern::to_seconds(now - last_);
    last_ = now;
    h_ += climb_gain_() * (actuators_.get().delta_t - 0.5) * dt;
    std::uniform_real_distribution<double> u(-noise_(), noise_());
    tern::msg::Imu m;
    m.stamp = now;
    m.accel = Eigen::Vector3d(u(rng_), u(rng_), -tern::kGravity + u(rng_));
    m.gyro = Eigen::Vector3d::Zero();
    imu_.publish(m);
    tern::msg::State s;
    s.stamp = now;
    s.p_d = -h_;
    s.Va = 15.0;
    s.valid = true;
    truth_.publish(s);
    ++steps_;
  }
  std::vector<std::pair<std::string, double>> summary() const override { return {{"final_altitude_m", h_}}; }

 private:
  tern::Input<tern::msg::Actuators> actuators_;
  tern::Output<tern::msg::Imu> imu_;
  tern::Output<tern::msg::State> truth_;
  tern::Param<double> climb_gain_, noise_, h0_;
  std::mt19937_64 rng_;
  double h_ = 0;
  tern::Nanos last_ = -1;
  long steps_ = 0;
};
}  // namespace

TERN_PLUGIN(TestSensor, "test_sensor", tern::PluginKind::io, "host test: point aircraft with seeded IMU noise")
