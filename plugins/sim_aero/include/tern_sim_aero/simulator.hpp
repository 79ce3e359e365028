// tern_sim_aero/simulator.hpp: the aircraft in its environment, advanced in fixed steps: servo
// lag and limits, wind (steady + Dryden + 1-cosine gusts), the uavbook model integrated by RK4,
// the ground, and crash detection. Plain C++ (no tern host types), used by the sim_aero plugin,
// the tern-aero tool, the tests and the benchmark.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "tern/aircraft.hpp"
#include "tern/aero/model.hpp"
#include "tern_sim_aero/wind.hpp"

namespace tern::sim {

/// Actuator imperfections beyond the aircraft file's servo lag (servo_tau). Zero: ideal.
struct ActuatorParams {
  double servo_rate_limit = 0.0;  ///< largest surface rate, rad/s (0: unlimited)
  double servo_deadband = 0.0;    ///< a surface moves only for a command error above deadband / 2, rad
  double motor_tau = 0.0;         ///< motor spin-up/down first-order time constant, s (0: at once)
};

/// Actuator set of a sensor profile (profiles.hpp): `realistic` = a hobby digital servo
/// (0.10 s per 60 deg at 6 V, i.e. 10.5 rad/s; 2 us deadband of a +-500 us, +-0.7 rad throw,
/// 0.003 rad) and an outrunner with a 2-bladed 10-12 in propeller (spin-up ~0.1 s); `rosflight`
/// and `ideal` = none. Throws std::invalid_argument for an unknown name.
ActuatorParams actuator_profile(std::string_view name);

class Simulator {
 public:
  /// `seed` drives the turbulence and random gusts. The state starts level at rest height at the
  /// origin (use set_state(rest_state(...)) for the settled attitude on the gear).
  Simulator(Aircraft ac, std::uint64_t seed);

  const Aircraft& aircraft() const { return ac_; }

  /// Sets the state (throws std::runtime_error "initial state: <field> is not finite" for NaN
  /// or infinite elements) and the actual surface positions (the servos start there).
  void set_state(const StateVector& x, const Deltas& surfaces = {});
  const StateVector& state() const { return x_; }

  /// Commanded inputs (clamped to the aircraft's limits and throttle to [0, 1]). Throws
  /// std::runtime_error "actuators: <field> is not finite" for NaN or infinite values.
  void set_command(const Deltas& cmd);
  const Deltas& command() const { return cmd_; }
  /// Rate limit, deadband and motor lag (from the next step on).
  void set_actuators(const ActuatorParams& p) { actuators_ = p; }
  /// Surface positions after the servo lag (what the aerodynamics sees).
  const Deltas& surfaces() const { return act_; }

  /// Steady wind in NED (m/s), turbulence and gusts. The steady wind takes effect at the next
  /// step(); sync_wind() applies it at once.
  void set_steady_wind(const Eigen::Vector3d& w_ned) { steady_ = w_ned; }
  /// Makes the wind acting now (wind(), evaluate()) the steady wind, without advancing the
  /// turbulence or the gusts (e.g. for the samples at t = 0).
  void sync_wind() { wind_.steady_ned = steady_; }
  void set_turbulence(const DrydenParams& p) { dryden_.set_params(p); }
  GustField& gusts() { return gusts_; }
  /// The wind acting now (steady + gusts in NED, turbulence in body).
  const Wind& wind() const { return wind_; }
  /// Total wind in NED (steady + gusts + turbulence rotated to NED), m/s.
  Eigen::Vector3d wind_ned() const;

  /// Advances by dt seconds (one RK4 step; the wind and surfaces are updated first and held over
  /// the step). Throws std::runtime_error if the state becomes non-finite.
  void step(double dt);
  /// Flight time since set_state / reset, s.
  double time() const { return t_; }

  /// Forces and moments at the current state with the current surfaces and wind.
  ForcesMoments evaluate() const;

  /// A crash: the CG went below the ground, a hard point (the gear's structure: wing tips, nose,
  /// tail) touched it, or a wheel touched down faster than the gear's max_sink_rate. The
  /// aircraft stops there (state frozen) until set_state.
  bool crashed() const { return crashed_; }
  /// Where and how the aircraft hit the ground (valid once crashed()): the state of the RK4
  /// step that crashed, before it was frozen, and what struck.
  struct Impact {
    double t = 0;                         ///< s since set_state
    StateVector x = StateVector::Zero();  ///< the state
    double Va = 0;                        ///< airspeed, m/s
    std::string what;                     ///< "the left wing tip struck the ground at 3.1 m/s (sink 2.0 m/s)", ...
    int hard_point = -1;                  ///< index in gear.structure of the point that struck, -1: none
    int wheel = -1;                       ///< index in gear.points of a wheel touching down too fast, -1: none
    double point_speed = 0;               ///< speed of that point (or of the CG), m/s
    double point_sink = 0;                ///< its sink rate (NED down), m/s
  };
  const Impact& impact() const { return impact_; }

  /// Restarts the wind random streams (same seed: same turbulence).
  void reset_wind();

 private:
  Aircraft ac_;
  std::uint64_t seed_;
  Rng rng_;
  StateVector x_ = StateVector::Zero();
  Deltas cmd_, act_;
  ActuatorParams actuators_;
  Eigen::Vector3d steady_ = Eigen::Vector3d::Zero();
  Dryden dryden_;
  GustField gusts_;
  Wind wind_;
  double t_ = 0;
  bool crashed_ = false;
  Impact impact_;
  /// 1 - exp(-dt / tau) of a first-order lag, remembered for the last dt and tau (the step is fixed).
  struct Lag {
    double dt = -1.0, tau = 0.0, k = 1.0;
    double operator()(double step, double time_constant);
  };
  Lag servo_lag_, motor_lag_;
  std::vector<bool> wheel_down_;  ///< each gear point on the ground after the last step
  bool ground_strike(Impact& m);
};

/// Names the first non-finite element of a state ("p_n", "e0", ...) or returns "".
std::string first_non_finite(const StateVector& x);

}  // namespace tern::sim
