// core/apps/commands/serve_command.cpp: `tern serve CONFIG`: one host kept alive across flights,
// driven over its control socket (serve.hpp; the clients: control_commands.cpp).
#include <memory>

#include "commands/commands.hpp"
#include "commands/host_preparation.hpp"
#include "commands/serve.hpp"

namespace tern::core {

namespace {

struct ServeOptions {
  std::string config;
  std::string socket = default_socket().string();
  std::optional<std::string> log_dir;
  bool realtime = false;
  RealtimeOptions rt;
  HostPreparation prep;
};

int serve_mission(const ServeOptions& o) {
  HostOptions opt;
  if (o.log_dir) opt.log_dir = fs::path(*o.log_dir);
  opt.realtime = o.realtime;
  opt.rt = o.rt;
  PreparedMission m = prepare_mission(o.config, o.prep);
  Host host(std::move(m.config), opt);
  host.build();
  if (!report_missions(check_missions(host))) return 1;  // as tern fly: refused before any flight
  const TickObservers observers(host, o.prep, m, o.realtime);
  return serve(host, o.socket, observers.console_url());
}

}  // namespace

Command add_serve_command(CLI::App& app) {
  auto o = std::make_shared<ServeOptions>();
  auto* c = app.add_subcommand("serve", "keep a host alive across flights; control it with swap, phases and remote");
  c->add_option("config", o->config, "mission config (YAML)")->required();
  c->add_option("--socket", o->socket, "control socket")->capture_default_str();
  c->add_option("--log-dir", o->log_dir, "directory for the run directories");
  add_realtime_options(c, o->realtime, o->rt, "pace each flight to wall time (the real-time figures: docs/companion-computer.md)");
  add_console_options(c, o->prep);
  add_gcs_options(c, o->prep);
  add_dds_options(c, o->prep);
  add_mission_override_options(c, o->prep);
  return {c, [o] { return serve_mission(*o); }};
}

}  // namespace tern::core
