// fuzz_campaign_file: libFuzzer target for the campaign file (core/apps/campaign/campaign_file.hpp
// load_campaign, `tern campaign FILE`) and what is drawn from it (dispersion.hpp
// resolve_dispersions and draw_flight): the bounded YAML load (tern/input_file.hpp), the file's
// keys, distributions, criteria and grid, then the dispersions checked against a catalogue of
// parameters shaped as the default mission's (a wind vector of 3, a turbulence choice, a heading
// for `into_wind`, reals, an integer, a free-length vector, a flag, a file path) and the
// Aerosonde's aircraft file, and the draws of the first, second and last flights and of the last
// grid point.
//
// Any bytes: one core::ConfigError whose line starts with the campaign file's path, or a campaign
// whose every draw the flight can fly: each drawn parameter value accepted by the parameter
// (ParamBase::validate: kind, size, range, choices), each perturbed aircraft number and each
// numeric table column finite. Never a crash, a hang, another exception, or an error that does
// not name the file. The file lies in a directory of its own under TMPDIR beside an empty
// base.yaml (the `base:` a seed names); nothing is written.
#include <cmath>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "campaign_file.hpp"
#include "config/error.hpp"
#include "dispersion.hpp"
#include "fuzz_input.hpp"

namespace {

using tern::ParamBase;
using tern::ParamSpec;

/// Parameters shaped as the default mission's, named as a campaign names them.
struct Catalogue {
  tern::Param<std::vector<double>> wind, imu_position;
  tern::Param<std::string> turbulence, aircraft;
  tern::Param<double> heading, gyro_noise, roll_kp, alt_toz;
  tern::Param<std::int64_t> loops;
  tern::Param<bool> flag;
  tern::campaign::ParamCatalogue params;

  template <class T>
  void add(tern::Param<T>& p, const std::string& qualified, ParamSpec spec, const T& value) {
    p.set_identity(qualified.substr(qualified.find('.') + 1), qualified, std::move(spec), value);
    p.init(value);
    params[qualified] = &p;
  }

  Catalogue() {
    add(wind, "sim.wind", ParamSpec("m/s", -50, 50, "steady wind NED").of_size(3), std::vector<double>{0, 0, 0});
    add(imu_position, "ekf.imu_position", ParamSpec("m", -5, 5, "IMU position FRD"), std::vector<double>{0.1, 0, 0});
    add(turbulence, "sim.turbulence", ParamSpec("", 0, 0, "turbulence").one_of({"none", "light", "moderate", "severe"}),
        std::string("light"));
    add(aircraft, "sim.aircraft", ParamSpec("", 0, 0, "aircraft file").as_path(), std::string("aerosonde.yaml"));
    add(heading, "sim.init_heading", ParamSpec("rad", -M_PI, M_PI, "initial heading"), 0.0);
    add(gyro_noise, "ekf.gyro_noise", ParamSpec("rad/s", 0, 1, "gyro noise"), 0.002);
    add(roll_kp, "slc.roll_kp", ParamSpec("", 0, 5, "roll gain"), 1.2);
    add(alt_toz, "phase_machine.alt_toz", ParamSpec("m", 0, 100, "take-off zone"), 10.0);
    add(loops, "path.loops", ParamSpec("", 0, 1000, "mission loops"), std::int64_t{2});
    add(flag, "ekf.use_mag", ParamSpec("", 0, 0, "fuse the magnetometer"), true);
  }
};

struct World {
  Catalogue catalogue;
  YAML::Node aircraft = YAML::LoadFile(TERN_FUZZ_AIRCRAFT_FILE);
};

World& world() {
  static World w;
  return w;
}

/// What a flight is handed: every value one its parameter accepts, every number finite.
void check(const tern::campaign::FlightDraw& f, const tern::campaign::ParamCatalogue& params) {
  for (const auto& [name, value] : f.params) {
    const auto it = params.find(name);
    if (it == params.end()) __builtin_trap();
    it->second->validate(value);  // throws ParamError: not caught below, so a finding
  }
  for (const auto& [path, number] : f.aircraft)
    if (!std::isfinite(number)) __builtin_trap();
  for (const auto& c : f.columns)
    if (std::isinf(c.number)) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  World& w = world();
  const auto file = tern::fuzz::in_dir(data, size, "campaign.yaml");
  const auto base = file.parent_path() / "base.yaml";
  if (!std::filesystem::exists(base)) std::ofstream(base) << "name: base\n";
  const std::string path = file.string();
  try {
    const tern::campaign::CampaignFile c = tern::campaign::load_campaign(file);
    if (c.flights < 1 || c.grid_points < 1) __builtin_trap();
    const auto resolved = tern::campaign::resolve_dispersions(c, w.catalogue.params, w.aircraft);
    for (const std::size_t k : {std::size_t{0}, std::size_t{1}, c.flights - 1, c.grid_points - 1})
      check(tern::campaign::draw_flight(c, resolved, k), w.catalogue.params);
  } catch (const tern::core::ConfigError& e) {
    tern::fuzz::note(e);
    if (std::string(e.what()).find(path) == std::string::npos) __builtin_trap();  // one line naming the file
  }
  return 0;
}
