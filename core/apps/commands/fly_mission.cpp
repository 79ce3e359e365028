#include "commands/fly_mission.hpp"

#include "commands/command_line.hpp"

namespace tern::core {

std::optional<FlightResult> fly_mission(const std::string& config_file, const HostPreparation& prep, const HostOptions& options,
                                        bool signals) {
  PreparedMission m = prepare_mission(config_file, prep);
  if (!report_missions(check_missions(m.config))) return std::nullopt;  // refused before anything flies
  Host host(std::move(m.config), options);
  host.build();
  if (signals) install_signal_handlers();
  const TickObservers observers(host, prep, m, options.realtime);
  return host.fly();
}

}  // namespace tern::core
