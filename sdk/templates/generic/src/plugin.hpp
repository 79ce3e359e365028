// @CLASS@: a flight monitor. It reads the state, warns in the flight's log when the airspeed
// drops below Va_warn while airborne, and adds its figures to the flight's summary.json.
// A starting point for any plugin that is not an estimator, controller, guidance or I/O.
//
// Ports:  in  state   msg::State (only valid states above min_altitude count as airborne)
// Parameters: Va_warn (m/s), min_altitude (m).
// Summary: <instance>.max_abs_phi (rad), .min_Va, .mean_Va (m/s), .time_below_Va_warn (s),
//          .low_airspeed_episodes.
// Per-flight state (tern/plugin.hpp): everything a flight changes is in `flight_`, which
// reset() replaces wholesale; a new figure, counter or "warned once" flag goes there.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>

#include "flight_stats.hpp"
#include "tern/plugin.hpp"

class @CLASS@ final : public tern::Plugin {
 public:
  void configure() override {
    using tern::ParamSpec;
    declare(state_, "state", "vehicle state");
    declare(Va_warn_, "Va_warn", 12.0, ParamSpec("m/s", 0.0, 100.0, "warn when the airspeed drops below this while airborne"));
    declare(min_altitude_, "min_altitude", 5.0, ParamSpec("m", -100.0, 10000.0, "height above the origin from which the aircraft counts as airborne"));
  }

  /// Between flights: as after configure() (no figures yet).
  void reset() override { flight_ = Flight{}; }

  void step(tern::Nanos now) override {
    if (!state_.updated()) return;
    const tern::msg::State& x = *state_;
    if (!x.valid || x.altitude() < min_altitude_()) return;
    if (flight_.stats.add(tern::to_seconds(now), x.phi, x.Va, Va_warn_()))
      log().warn("t = {:.2f} s: airspeed {:.1f} m/s below {:.1f} m/s at {:.0f} m", tern::to_seconds(now), x.Va, Va_warn_(),
                 x.altitude());
  }

  std::vector<std::pair<std::string, double>> summary() const override {
    const tern_@NAME@::FlightStats& s = flight_.stats;
    return {{"max_abs_phi", s.max_abs_phi()},
            {"min_Va", s.min_Va()},
            {"mean_Va", s.mean_Va()},
            {"time_below_Va_warn", s.time_below_warn()},
            {"low_airspeed_episodes", static_cast<double>(s.episodes())}};
  }

 private:
  tern::Input<tern::msg::State> state_;
  tern::Param<double> Va_warn_, min_altitude_;
  /// What a flight changes; reset() replaces it with a fresh one.
  struct Flight {
    tern_@NAME@::FlightStats stats;  ///< the figures of summary()
  } flight_;
};
