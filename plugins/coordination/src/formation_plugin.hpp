// coord_formation: leader-follower formation on one orbit (tern/coordination/formation.hpp: the
// followers' airspeed holds an along-orbit spacing behind the leader; each vehicle's own path
// follower flies the orbit, uavbook sec. 10.3).
//
// Once every vehicle is ready (fleet.hpp, start_phase), each follower k (k = 1, 2, ... in the
// mission's vehicle order without the leader) is sent a new list (set_current) of one loiter
// item: the orbit (center, radius, direction) at the centre's altitude raised by
// k * altitude_offset, with no time limit; with orbit_leader the leader gets the same orbit at
// Va_nominal (otherwise it flies its own mission, which should orbit there). Every
// update_period the followers' airspeeds are recomputed from the estimates; a follower gets a
// new list only when its command moved by more than Va_tolerance (no thrashing).
// Errors: configure() throws ParamError naming the vehicle when `leader` is not one of the
// mission's vehicles, and for an inconsistent orbit or speed range.
//
// Summary: formation_start (s, -1: never started), spacing_rms (m: RMS of every follower's arc
// error from settle_time after the start on), spacing_rms_<vehicle>, spacing_error_max (m, the
// largest |error| in that window), spacing_samples, orbit_updates, mission_edits.
// Per-flight state (tern/plugin.hpp) in `flight_` (and the fleet's), replaced by reset().
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fleet.hpp"
#include "tern/coordination/formation.hpp"

namespace tern::coord {

class FormationPlugin final : public FleetPlugin {
 public:
  void configure() override;
  void step(Nanos now) override;
  void reset() override;
  std::vector<std::pair<std::string, double>> summary() const override;

 private:
  FormationConfig config() const;
  void start_formation(double t, const std::vector<std::optional<Observed>>& obs);
  void track(double t, const std::vector<std::optional<Observed>>& obs);
  void send_orbit(std::size_t i, int k, double Va);
  /// Follower number of vehicle i (0: the leader).
  int follower_number(std::size_t i) const;

  Param<std::string> leader_;
  Param<std::vector<double>> center_;
  Param<double> radius_, spacing_, altitude_offset_, gain_, Va_min_, Va_nominal_, Va_max_, update_period_, Va_tolerance_, settle_time_;
  Param<std::int64_t> direction_;
  Param<bool> orbit_leader_;
  std::size_t leader_index_ = 0;

  struct Vehicle {
    double Va_sent = 0.0;  ///< m/s
    double sum_sq = 0.0;   ///< m^2, arc errors squared after settling
    std::uint64_t samples = 0;
  };
  struct Flight {
    std::vector<Vehicle> v;
    std::optional<double> t_start;  ///< s
    double last_update = -std::numeric_limits<double>::infinity();
    double error_max = 0.0;  ///< m
    std::uint64_t updates = 0;
    bool waiting_logged = false;
  } flight_;
};

}  // namespace tern::coord
