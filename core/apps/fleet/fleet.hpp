// core/apps/fleet/fleet.hpp: a multi-vehicle flight: N vehicles and their coordination in one
// deterministic world, on one clock (docs/multi-vehicle.md).
//
// Each vehicle is a Host of its own (its plugin stack, port graph, phase machine, failsafes,
// flight log), built from its part of the fleet config (fleet_config.hpp) with its own seed,
// tern::derive_seed(seed, name) (tern/random.hpp) as an instance's is derived. The coordination plugins are one
// more Host, whose port graph is offered mirrors of every vehicle topic as "<vehicle>/<topic>".
// Every tick, at flight time t:
//   1. each vehicle flies its tick, in `vehicles:` order           Host::tick
//   2. the mirrors take the vehicles' new messages (a copy when the sequence moved)
//   3. the separation monitor looks at every pair                   separation.hpp
//      (a conflict's `hold` response is a mission edit to the pair's later vehicle)
//   4. the coordination host flies its tick; what it published on "<vehicle>/mission_edit"
//      goes to that vehicle's path planner, applied at the start of its next tick.
// A vehicle whose flight ends (landed, crashed, a failed isolated plugin, its duration) is left
// out of later ticks; the others fly on. The flight ends when every vehicle's has; then the
// coordination's ends ("vehicles_ended"). The run directory holds fleet.json, summary.json (the
// vehicles' end reasons, the separation report, the coordination's figures) and one flight log
// per vehicle (<run>/<vehicle>/) and for the coordination (<run>/coordination/).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "fleet/fleet_config.hpp"
#include "fleet/separation.hpp"
#include "flight/host.hpp"
#include "tern/geodesy.hpp"

namespace tern::core {

struct FleetOptions {
  std::optional<std::uint64_t> seed;  ///< the fleet's (each vehicle's derives from it)
  std::optional<double> duration;     ///< s
  std::optional<fs::path> log_dir;    ///< parent of the run directory
  bool quiet = false;                 ///< no console log below warnings, no end-of-flight tables
  bool describing = false;            ///< configure only (tern check): open no files or devices
  bool realtime = false;              ///< paced to wall time (each vehicle's host paces; the first waits)
};

struct FleetResult {
  fs::path run_dir;
  std::vector<std::pair<std::string, FlightResult>> vehicles;  ///< in `vehicles:` order
  std::optional<FlightResult> coordination;
  nlohmann::ordered_json summary;  ///< what summary.json holds
  double wall_s = 0;               ///< wall time of the flight, first tick to last (timing.json)
  bool ok() const;                 ///< every vehicle's and the coordination's flight ok
};

class Fleet {
 public:
  Fleet(FleetConfig config, FleetOptions options);
  ~Fleet();  ///< the coordination host (it reads the mirrors) first, then the vehicles
  Fleet(const Fleet&) = delete;
  Fleet& operator=(const Fleet&) = delete;

  /// Builds every vehicle's host, then the coordination's. Throws ConfigError (one line naming
  /// the vehicle or the coordination instance and the field).
  void build();
  /// Flies the fleet's one flight (build() first).
  FleetResult fly();

  const FleetConfig& config() const { return config_; }
  std::size_t size() const { return vehicles_.size(); }
  Host& vehicle(std::size_t i) { return *vehicles_[i].host; }
  const std::string& vehicle_name(std::size_t i) const { return vehicles_[i].name; }
  Host* coordination() { return coordination_.get(); }
  std::uint64_t seed() const { return seed_; }
  /// Where the other vehicles estimate they are, in vehicle `focus`'s own NED frame (its
  /// estimator's origin), for a view from that vehicle (the console); vehicles without an
  /// estimate yet, and every one while `focus` has none, are left out. Call on the flight thread
  /// (a tick observer).
  struct Track {
    std::string name;
    Eigen::Vector3d ned;  ///< m
    double psi = 0;       ///< rad
  };
  std::vector<Track> others_seen_from(std::size_t focus);

 private:
  struct Vehicle {
    std::string name;
    std::unique_ptr<Host> host;
    bool active = false;
    FlightResult result;
    std::optional<GeoPoint> origin_seen;                      // the estimate's origin its offset was computed for
    Eigen::Vector3d origin_offset = Eigen::Vector3d::Zero();  // its origin in the common frame, m
  };
  struct Mirror {
    std::size_t vehicle;
    std::string topic;  // the vehicle's
    std::unique_ptr<OutputBase> out;
    bool read = false;  // a coordination input is bound to it
  };
  struct Edits {
    std::size_t vehicle;
    const OutputBase* out;  // a coordination output "<vehicle>/mission_edit"
    std::uint64_t seen = 0;
  };

  void build_vehicle(std::size_t i);
  void make_mirrors();
  void build_coordination();
  void check_coordination_ports(const std::vector<std::unique_ptr<Instance>>& instances) const;
  void tick_world(Nanos now);
  void copy_mirrors();
  void watch_separation(Nanos now);
  void hold(std::size_t v, Nanos now);
  void forward_edits();
  std::optional<Eigen::Vector3d> estimated_position(Vehicle& v);
  std::optional<Eigen::Vector3d> true_position(const Vehicle& v);
  nlohmann::ordered_json summary(const FleetResult& r) const;
  void write_documents(const FleetResult& r) const;

  FleetConfig config_;
  FleetOptions options_;
  std::uint64_t seed_ = 1;
  fs::path run_dir_;
  std::vector<Vehicle> vehicles_;
  std::vector<Mirror> mirrors_;
  std::unique_ptr<Host> coordination_;
  std::vector<Edits> edits_;
  std::optional<GeoOrigin> common_;  // the frame the monitor compares in: the world's origin
  std::unique_ptr<SeparationMonitor> separation_;
  std::shared_ptr<spdlog::logger> log_;
};

}  // namespace tern::core
