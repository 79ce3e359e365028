// core/apps/commands/fleet_command.cpp: `tern fly` and `tern check` of a multi-vehicle mission
// (fleet_config.hpp): the command line's options applied to every vehicle, then the fleet flown
// (fleet.hpp) or described.
//
// --set ITEM goes to the part that has the instance: "uav2.slc.roll_kp=0.4" to vehicle uav2's
// slc, "rendezvous.Va_max=20" to a coordination instance, "slc.roll_kp=0.4" to every vehicle's.
#include <cstdio>

#include <fmt/format.h>

#include "commands/fleet_command.hpp"
#include "config/error.hpp"
#include "fleet/fleet.hpp"

namespace tern::core {

namespace {

std::string first_word(const std::string& item) { return item.substr(0, std::min(item.find('.'), item.find('='))); }

bool is_coordination_instance(const FleetConfig& fc, const std::string& name) {
  if (!fc.coordination) return false;
  for (const auto& ic : fc.coordination->plugins)
    if (ic.name == name) return true;
  return false;
}

// The --set items for `part` (a vehicle's name, or "coordination").
std::vector<std::string> sets_for(const FleetConfig& fc, const std::vector<std::string>& sets, const std::string& part) {
  std::vector<std::string> out;
  for (const auto& item : sets) {
    const std::string first = first_word(item);
    bool vehicle_item = false;
    for (const auto& v : fc.vehicles) vehicle_item = vehicle_item || v.name == first;
    if (vehicle_item) {
      if (first == part) out.push_back(item.substr(first.size() + 1));
    } else if (is_coordination_instance(fc, first) == (part == "coordination")) {
      out.push_back(item);
    }
  }
  return out;
}

}  // namespace

std::vector<PreparedMission> prepare_fleet(FleetConfig& fc, const HostPreparation& p) {
  std::vector<PreparedMission> out;
  for (auto& v : fc.vehicles) {
    HostPreparation pv = p;
    pv.overrides.sets = sets_for(fc, p.overrides.sets, v.name);
    try {
      out.push_back(prepare_loaded(v.config, pv));
    } catch (const ConfigError& e) {
      throw ConfigError(std::string(e.what()) + " (vehicle " + v.name + ")");
    }
    v.config = out.back().config;
  }
  if (fc.coordination) {
    HostPreparation pc;
    pc.overrides.sets = sets_for(fc, p.overrides.sets, "coordination");
    pc.log_level = p.log_level;
    pc.log_format = p.log_format;
    fc.coordination = prepare_loaded(*fc.coordination, pc).config;
  }
  return out;
}

int fly_fleet(const std::string& file, const FleetFlyOptions& o) {
  FleetConfig fc = load_fleet(file);
  std::size_t focus = 0;  // the console's vehicle
  for (std::size_t i = 0; i < fc.vehicles.size(); ++i)
    if (fc.vehicles[i].name == o.console_vehicle) focus = i;
  if (!o.console_vehicle.empty() && fc.vehicles[focus].name != o.console_vehicle)
    throw ConfigError("--console-vehicle: no vehicle named '" + o.console_vehicle + "' in " + fc.file.string());
  const std::vector<PreparedMission> prepared = prepare_fleet(fc, o.prep);
  for (const auto& m : prepared)
    if (!report_missions(check_missions(m.config))) return 1;
  Fleet fleet(std::move(fc), o.fleet);
  fleet.build();
  install_signal_handlers();
  FleetResult r;
  {
    // each vehicle's DDS bridge, in its namespace; the console on the focused vehicle, drawing the
    // others as traffic on its track; the MAVLink endpoint: every vehicle on its one port, each
    // with its system id
    std::vector<std::unique_ptr<TickObservers>> observers;
    std::vector<mavlink::LinkedVehicle> linked;
    for (std::size_t i = 0; i < fleet.size(); ++i) {
      HostPreparation p = o.prep;
      p.console = o.prep.console && i == focus;
      p.gcs.reset();
      observers.push_back(std::make_unique<TickObservers>(fleet.vehicle(i), p, prepared[i], o.fleet.realtime));
      linked.push_back({&fleet.vehicle(i), fleet.vehicle_name(i), fleet.config().vehicles[i].system_id});
    }
    std::unique_ptr<GcsEndpoint> gcs;
    if (o.prep.gcs) gcs = std::make_unique<GcsEndpoint>(o.prep, linked);
    if (Console* console = observers[focus]->console())
      console->set_traffic([&fleet, focus] {
        std::vector<Traffic> out;
        for (const auto& t : fleet.others_seen_from(focus)) out.push_back({t.name, t.ned.x(), t.ned.y(), -t.ned.z(), t.psi});
        return out;
      });
    r = fleet.fly();
  }
  std::printf("fleet '%s': %zu vehicles\n", fleet.config().name.c_str(), fleet.size());
  for (const auto& [name, f] : r.vehicles) std::printf("  %-12s %s, %.1f s\n", name.c_str(), f.end_reason.c_str(), to_seconds(f.flown));
  if (r.coordination) std::printf("  %-12s %s\n", "coordination", r.coordination->end_reason.c_str());
  const auto& sep = r.summary["separation"];
  if (!sep["closest_approach_m"].is_null())
    std::printf("closest approach: %.1f m (%s, %s and %s at t = %.1f s); %d conflicts below %.0f m\n",
                sep["closest_approach_m"].get<double>(), sep["from"].get<std::string>().c_str(), sep["pair"][0].get<std::string>().c_str(),
                sep["pair"][1].get<std::string>().c_str(), sep["t_s"].get<double>(), sep["conflicts"].get<int>(),
                sep["min_distance_m"].get<double>());
  std::printf("log: %s\n", r.run_dir.c_str());
  return r.ok() ? 0 : 1;
}

int check_fleet(const std::string& file, const HostPreparation& p) {
  FleetConfig fc = load_fleet(file);
  const std::vector<PreparedMission> prepared = prepare_fleet(fc, p);
  FleetOptions opt;
  opt.describing = opt.quiet = true;
  Fleet fleet(std::move(fc), opt);
  fleet.build();
  bool ok = true;
  for (std::size_t i = 0; i < fleet.size(); ++i) {
    std::printf("== vehicle %s (seed %llu)\n", fleet.vehicle_name(i).c_str(),
                static_cast<unsigned long long>(*fleet.vehicle(i).options().seed));
    std::fputs(fleet.vehicle(i).graph_text().c_str(), stdout);
    ok = report_missions(check_missions(fleet.vehicle(i)), true) && ok;
  }
  if (Host* c = fleet.coordination()) {
    std::printf("== coordination\n");
    std::fputs(c->graph_text().c_str(), stdout);
  }
  if (ok) std::printf("config OK: %s (%zu vehicles)\n", fleet.config().file.c_str(), fleet.size());
  return ok ? 0 : 1;
}

}  // namespace tern::core
