// core/apps/commands/vehicle_commands.cpp: the commands against a running `tern fly --dds` (or
// `serve --dds`) over DDS (core/apps/dds): topics, echo, hz, param (list, get, describe, set, save) and
// mission (add, clear, load, print), go-around. Each finds the vehicle by domain and namespace, or by a
// mission config's dds: section, and uses the DDS Security of dds_command.hpp.
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <utility>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "commands/commands.hpp"
#include "commands/dds_command.hpp"
#include "dds_bridge.hpp"
#include "fleet/fleet_config.hpp"
#include "flight/host.hpp"
#include "topic_tools.hpp"

namespace tern::core {

namespace {

/// Prints what a vehicle answered (any participant on the DDS domain may answer) with its control
/// characters escaped (terminal_text): an escape sequence in a name or a string field never reaches
/// the terminal raw.
template <class... Args>
void print_remote(fmt::format_string<Args...> format, Args&&... args) {
  std::fputs(terminal_text(fmt::format(format, std::forward<Args>(args)...)).c_str(), stdout);
}

/// How a client finds and talks to the vehicle.
struct ClientOptions {
  std::string config;  ///< a mission config whose dds: gives domain, namespace, interfaces and peers
  std::string ns = "tern";
  std::string vehicle;  ///< a multi-vehicle mission's vehicle (docs/multi-vehicle.md): its namespace
  std::uint32_t domain = 0;
  double timeout = 3.0;  ///< s
  std::optional<std::uint64_t> request_id;
  std::optional<std::string> keystore, enclave;
};

/// Adds a client subcommand with the options every client takes.
CLI::App* add_client(CLI::App& app, const std::string& name, const std::string& description, ClientOptions& o) {
  auto* c = app.add_subcommand(name, description);
  c->add_option("--domain", o.domain, "DDS domain id of the vehicle")->check(CLI::Range(0, 232));
  c->add_option("--namespace", o.ns, "vehicle namespace")->capture_default_str();
  c->add_option("--config", o.config, "take domain, namespace, interfaces and peers from this mission config's dds:");
  c->add_option("--vehicle", o.vehicle, "a multi-vehicle mission's vehicle: its namespace (with --config: that vehicle's dds:)");
  c->add_option("--timeout", o.timeout, "seconds to wait for the vehicle")->capture_default_str()->check(CLI::Range(0.001, 86400.0));
  // 1 .. 2^63-1: the ids a vehicle remembers (answered_requests.hpp); another would be applied again
  c->add_option("--request-id", o.request_id, "repeat a request that timed out with the id its error gave (applied once)")
      ->check(CLI::Range(std::uint64_t{1}, (std::uint64_t{1} << 63) - 1));
  c->add_option("--keystore", o.keystore, "DDS Security keystore (tern dds keystore create; default: $TERN_DDS_KEYSTORE)");
  c->add_option("--enclave", o.enclave, "enclave of the keystore to use (default: $TERN_DDS_ENCLAVE, else ground)");
  return c;
}

/// Connects as `o` (and the options given on `c`) says and runs `action`; a DdsError becomes one
/// error line and exit status 1.
int with_client(const CLI::App* c, const ClientOptions& o, const std::function<int(DdsClient&)>& action) {
  DdsOptions dopt;
  if (!o.config.empty()) {
    if (is_fleet_file(o.config) && o.vehicle.empty())
      return fail(o.config + ": a multi-vehicle mission: name the vehicle (--vehicle NAME)");
    const MissionConfig mc = is_fleet_file(o.config) ? load_fleet_part(o.config, o.vehicle) : load_config(o.config);
    dopt = parse_dds_options(mc.dds, mc.file);
  }
  if (c->count("--domain")) dopt.domain = o.domain;
  if (c->count("--namespace") || o.config.empty()) dopt.ns = o.ns;
  // a fleet's vehicle is bridged under its name, below the mission's namespace when one is given
  if (!o.vehicle.empty() && o.config.empty()) dopt.ns = c->count("--namespace") && !o.ns.empty() ? o.ns + "/" + o.vehicle : o.vehicle;
  try {
    apply_client_security(dopt, o.keystore, o.enclave);
    DdsClient client(dopt, std::chrono::milliseconds(static_cast<long>(o.timeout * 1000)));
    if (o.request_id) client.set_request_id(*o.request_id);
    return action(client);
  } catch (const DdsError& e) {
    return fail(e.what());
  }
}

Command add_topics(CLI::App& app) {
  auto o = std::make_shared<ClientOptions>();
  auto* c = add_client(app, "topics", "list the vehicle's DDS topics and their types", *o);
  return {c, [c, o] {
            return with_client(c, *o, [](DdsClient& client) {
              const DdsStatus st = client.status();
              print_remote("vehicle: mission '{}' ({}), {}{}\n", st.mission, st.config_file, st.flying ? "flying" : "idle",
                           st.flying ? fmt::format(" t={:.1f} s phase {}", st.flight_time, st.phase) : "");
              for (const auto& [name, type] : st.topics) print_remote("{:<40} {}\n", name, type);
              return 0;
            });
          }};
}

Command add_echo(CLI::App& app) {
  struct Options : ClientOptions {
    std::string topic, field;
    bool once = false;
  };
  auto o = std::make_shared<Options>();
  auto* c = add_client(app, "echo", "print a bridged topic's live values", *o);
  c->add_option("topic", o->topic, "tern topic name, e.g. state")->required();
  c->add_flag("--once", o->once, "print one sample and exit");
  c->add_option("--field", o->field, "print only this field (e.g. p_n, quat, header.stamp)");
  return {c, [c, o] {
            return with_client(c, *o, [&o = *o](DdsClient& client) {
              client.echo(o.topic, [&](const std::string& sample) {
                const auto f = o.field.empty() ? std::optional<std::string>(sample) : sample_field(sample, o.field);
                if (!f) throw DdsError("topic '" + o.topic + "' has no field '" + o.field + "'");
                print_remote("{}---\n", *f);
                std::fflush(stdout);
                return !o.once && stop_signal() == 0;
              });
              return 0;
            });
          }};
}

Command add_hz(CLI::App& app) {
  struct Options : ClientOptions {
    std::string topic;
    std::optional<double> duration;  ///< s
  };
  auto o = std::make_shared<Options>();
  auto* c = add_client(app, "hz", "the receive rate of a topic, every second (as ros2 topic hz)", *o);
  c->add_option("topic", o->topic, "tern topic name, e.g. state")->required();
  c->add_option("--duration", o->duration, "stop after this many seconds")->check(CLI::PositiveNumber);
  return {c, [c, o] { return with_client(c, *o, [&o = *o](DdsClient& client) { return topic_hz(client, o.topic, o.duration); }); }};
}

Command add_param(CLI::App& app) {
  struct Options : ClientOptions {
    std::string prefix, name, value, file;
    bool overwrite = false;
    CLI::App *list = nullptr, *get = nullptr, *describe = nullptr, *set = nullptr, *save = nullptr;
  };
  auto o = std::make_shared<Options>();
  auto* c = add_client(app, "param", "the vehicle's parameters over DDS: list, get, set, save", *o);
  c->require_subcommand(1);
  c->fallthrough();  // --domain etc. may follow `param set NAME VALUE`
  o->list = c->add_subcommand("list", "every parameter (or those starting with PREFIX)");
  o->list->add_option("prefix", o->prefix, "e.g. slc.");
  o->get = c->add_subcommand("get", "one parameter");
  o->get->add_option("name", o->name, "instance.param")->required();
  o->describe = c->add_subcommand("describe", "one parameter's descriptor (rcl_interfaces describe_parameters)");
  o->describe->add_option("name", o->name, "instance.param")->required();
  o->set = c->add_subcommand(
      "set", "change a parameter (validated; applied at the next tick, a start-only one when the next flight starts; logged)");
  o->set->add_option("name", o->name, "instance.param")->required();
  o->set->add_option("value", o->value, "a number, true/false, text, or [a, b, c]")->required();
  o->save = c->add_subcommand("save", "write every parameter to a YAML file on the vehicle");
  o->save->add_option("file", o->file, "file name on the vehicle (inside its log directory or dds.param_dirs)")->required();
  o->save->add_flag("--overwrite", o->overwrite, "replace an existing file");
  return {c, [c, o] {
            return with_client(c, *o, [&o = *o](DdsClient& client) {
              auto show = [](const DdsParam& p) {
                print_remote("{:<34} {:<16} (default {}, {}{}) {}\n", p.name, to_string(p.value), to_string(p.default_value),
                             p.unit.empty() ? "" : p.unit + ", ", fmt::format("[{}, {}]", p.min, p.max), p.description);
              };
              if (o.list->parsed()) {
                for (const auto& p : client.param_list(o.prefix)) show(p);
              } else if (o.get->parsed()) {
                show(client.param_get(o.name));
              } else if (o.describe->parsed()) {
                print_remote("{}", describe_param(client.param_get(o.name)));
              } else if (o.set->parsed()) {
                const ParamValue v = to_param_value(YAML::Load(o.value), "command line", o.name);
                const bool start_only = client.param_get(o.name).read_only;  // the vehicle refuses those in flight
                client.param_set(o.name, v);
                print_remote(
                    "{} = {} ({})\n", o.name, to_string(v),
                    start_only ? "start-only: takes effect when the vehicle's next flight starts" : "applied at the vehicle's next tick");
              } else if (o.save->parsed()) {
                print_remote("saved: {}\n", client.param_save(o.file, o.overwrite));
              }
              return 0;
            });
          }};
}

Command add_mission(CLI::App& app) {
  struct Options : ClientOptions {
    std::vector<double> w;
    bool lla = false, use_chi = false, set_current = false;
    double chi = 0, Va = 0;
    std::optional<double> land;  ///< a land item's runway heading, rad
    msg::Waypoint spec;          ///< a land item's glide slope and heights (msg::Waypoint's defaults)
    std::string file;
    CLI::App *add = nullptr, *load = nullptr, *print = nullptr;
  };
  auto o = std::make_shared<Options>();
  auto* c = add_client(app, "mission", "the vehicle's mission over DDS: add, clear, load, print", *o);
  c->require_subcommand(1);
  c->fallthrough();
  o->add = c->add_subcommand("add", "add a waypoint (ROSplane's AddWaypoint)");
  o->add->add_option("w", o->w, "north east down (m), or lat lon alt with --lla")->required()->expected(3);
  o->add->add_flag("--lla", o->lla, "w is latitude (deg), longitude (deg), altitude (m MSL)");
  o->add->add_option("--chi", o->chi, "desired course at the waypoint, rad");
  o->add->add_flag("--use-chi", o->use_chi, "fly a Dubins path to arrive at --chi");
  o->add->add_option("--Va", o->Va, "desired airspeed, m/s")->required()->check(CLI::PositiveNumber);
  o->add->add_flag("--set-current", o->set_current, "start a new list with this waypoint, now");
  o->add->add_option("--land", o->land, "a land item: w is the touchdown point, this the runway heading, rad (tern's add_mission_item)")
      ->excludes("--chi")
      ->excludes("--use-chi");
  o->add->add_option("--glide-slope", o->spec.land_glide_slope, "land: glide-path angle, rad, (0, 0.35]")->needs("--land");
  o->add->add_option("--flare-height", o->spec.land_flare_height, "land: flare begins this high above the touchdown point, m")
      ->needs("--land");
  o->add->add_option("--decision-height", o->spec.land_decision_height, "land: stabilised below this height or go around, m")
      ->needs("--land");
  c->add_subcommand("clear", "remove every waypoint (the aircraft orbits the origin)");
  o->load = c->add_subcommand("load", "replace the mission with a waypoint file on the vehicle");
  o->load->add_option("file", o->file, "tern or ROSplane waypoint file")->required();
  o->print = c->add_subcommand("print", "the vehicle's current waypoints");
  return {c, [c, o] {
            return with_client(c, *o, [&o = *o](DdsClient& client) {
              if (o.add->parsed()) {
                msg::Waypoint wp = o.spec;
                wp.w = Eigen::Vector3d(o.w[0], o.w[1], o.w[2]);
                wp.lla = o.lla;
                wp.chi_d = o.land.value_or(o.chi);
                wp.use_chi = o.use_chi;
                wp.Va_d = o.Va;
                if (o.land) wp.type = msg::Waypoint::land;
                client.mission_add(wp, o.set_current, true);
                print_remote("{} added\n", o.land ? "land item" : "waypoint");
              } else if (o.load->parsed()) {
                client.mission_load(o.file);
                print_remote("mission loaded: {}\n", o.file);
              } else if (o.print->parsed()) {
                print_remote("{}\n", client.mission_print());
              } else {
                client.mission_clear();
                print_remote("mission cleared\n");
              }
              return 0;
            });
          }};
}

Command add_go_around(CLI::App& app) {
  auto o = std::make_shared<ClientOptions>();
  auto* c = add_client(app, "go-around",
                       "abandon the landing under way: climb out and come round for another approach (taken on the final approach "
                       "and in the flare; the path manager's land_attempts bound the approaches)",
                       *o);
  return {c, [c, o] {
            return with_client(c, *o, [](DdsClient& client) {
              print_remote("{}\n", client.go_around());
              return 0;
            });
          }};
}

}  // namespace

std::vector<Command> add_vehicle_commands(CLI::App& app) {
  return {add_topics(app), add_echo(app), add_hz(app), add_param(app), add_mission(app), add_go_around(app)};
}

}  // namespace tern::core
