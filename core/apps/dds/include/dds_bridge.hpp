// core/apps/dds/include/dds_bridge.hpp: the DDS bridge (issue 8). Publishes tern topics over Fast DDS
// and serves parameters, mission edits and status on ROS 2's wire conventions:
//   topics    rt/<namespace>/<name>, types rosplane_msgs::msg::dds_::State_ ... (ROSplane's
//             State, ControllerCommands, ControllerInternals, CurrentPath, Waypoint) and
//             tern_msgs::msg::dds_::* for tern's own messages (sensors, actuators, flight phase,
//             waypoint list, parameters);
//   services  rq/<namespace>/<service>Request, rr/<namespace>/<service>Reply, replies matched to
//             requests by sample identity (Fast DDS related_sample_identity, as rmw_fastrtps).
// Fast DDS stays behind this header (pimpl): include it freely in core/apps.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "tern/msg/path.hpp"
#include "tern/param.hpp"

namespace YAML {
class Node;
}

namespace tern::core {

class Host;

/// Quality of service of a bridged topic (the history depth is DdsTopicOptions::depth).
enum class DdsQos : std::uint8_t {
  best_effort,      ///< telemetry: best-effort, keep-last (default 1), volatile
  reliable,         ///< reliable, keep-last (default 10), volatile: rclcpp's default QoS
  transient_local,  ///< reliable, keep-last (default 1), transient-local (late joiners get the last samples)
};

/// Keep-last depth of a QoS when a topic gives none: best_effort 1, reliable 10, transient_local 1.
int default_depth(DdsQos q);

struct DdsTopicOptions {
  std::string topic;          ///< tern topic name (e.g. "state")
  std::string name;           ///< DDS name under the namespace (default: topic)
  double rate = -1;           ///< max publish rate, Hz (0: every message; <0: the bridge default)
  std::optional<DdsQos> qos;  ///< default: transient_local for waypoints and flight_phase, else best_effort
  std::optional<int> depth;   ///< keep-last depth, 1..1000 (default: default_depth(qos))
  /// ROS 2 type ("sensor_msgs/msg/Imu"); empty: the tern type's first DDS type (src/convert.cpp).
  std::string type;
};

/// Which clock header stamps and /clock follow (docs/ros2.md).
enum class DdsTime : std::uint8_t {
  automatic,  ///< wall with a real FCU (an instance of plugin fcu_serial), sim otherwise
  sim,        ///< stamp = flight time (sim time from 0), published on rt/clock
  wall,       ///< stamp = the wall clock (UNIX time) of the flight's first tick + flight time; no /clock
};

/// DDS Security (src/security.hpp): the OMG DDS Security 1.1 builtin plugins (PKI-DH
/// authentication, signed governance and permissions, AES-GCM-GMAC encryption) with the files of
/// enclave `enclave` of an SROS2-style keystore (`tern dds keystore create|add-node`).
struct DdsSecurity {
  std::filesystem::path keystore;  ///< the keystore directory (public/, private/, enclaves/)
  std::string enclave;             ///< enclaves/<enclave>/ holds this participant's files
};

struct DdsOptions {
  bool enabled = false;                              ///< `dds: {enabled: true}` or `tern fly --dds`
  std::uint32_t domain = 0;                          ///< DDS domain id, 0..232
  std::string ns = "tern";                           ///< vehicle namespace: topics rt/<ns>/<name> ("" : rt/<name>)
  std::vector<std::string> interfaces{"127.0.0.1"};  ///< IPv4 addresses the participant may use
  std::vector<std::string> peers{"127.0.0.1"};       ///< initial discovery peers (IPv4)
  bool multicast = false;                            ///< multicast discovery on the listed interfaces
  double rate = 0;                                   ///< default max publish rate per topic, Hz (0: every message)
  std::vector<DdsTopicOptions> topics;               ///< bridged topics (default: rosplane_profile(aliases))
  /// With the default topics, also publish tern's own names that ROSplane's profile renames
  /// (state, waypoints, actuators in tern's types and QoS), for tern's tools and older scripts.
  bool aliases = true;
  bool topics_from_config = false;  ///< `dds.topics` was given (each named topic must exist)
  DdsTime time = DdsTime::automatic;
  double clock_rate = 100;  ///< Hz of rt/clock in sim time (0: no /clock)
  /// Serve telemetry only: no parameter, mission or file service (status stays, for `tern topics`).
  bool read_only = false;
  /// Directories where load_mission_from_file may read, besides the mission config's directory.
  std::vector<std::filesystem::path> mission_dirs;
  /// Directories where param_save may write, besides the run directories' parent (log.dir).
  std::vector<std::filesystem::path> param_dirs;
  /// `dds.security: {keystore: DIR, enclave: NAME}`: secure participants only (default: off).
  std::optional<DdsSecurity> security;
  /// The default topics: ROSplane 2.0's and rosflight_io's names, types and QoS (core/apps/dds/README.md
  /// lists each with the source file it was read from), then, with `aliases`, tern's own names.
  static std::vector<DdsTopicOptions> rosplane_profile(bool aliases);
  /// True when every interface is 127.0.0.1 and multicast is off.
  bool loopback_only() const;
};

/// Reads the mission config's `dds:` section (missing or null: defaults). Keys: enabled, domain,
/// namespace, interfaces, peers, multicast, rate, topics (a list of names or of maps
/// {topic, name, rate, qos, depth, type}), aliases, time (auto | sim | wall), clock_rate, read_only, mission_dirs, param_dirs (lists of
/// directories, relative to the config file), security ({keystore: DIR relative to the config file, enclave: NAME, default "vehicle"}).
/// Throws ConfigError "file:line:col: dds.key: ..." for unknown keys (with a suggestion) and bad values.
DdsOptions parse_dds_options(const YAML::Node& dds, const std::filesystem::path& config_file);

/// A DDS error: no vehicle answered, a request was refused, a topic is unknown. what() is one line.
class DdsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The vehicle side: attach it to a built Host before host.fly(); destroy it after the last
/// flight and before the Host. It registers the Host's tick observer (publishing the bridged
/// topics whose sequence changed, rate-limited) and answers service requests on Fast DDS threads
/// through the Host's thread-safe API. Throws ConfigError when a bridged topic is unknown or has
/// no DDS type, DdsError when Fast DDS cannot create the participant.
class DdsBridge {
 public:
  DdsBridge(Host& host, const DdsOptions& options);
  ~DdsBridge();
  DdsBridge(const DdsBridge&) = delete;
  DdsBridge& operator=(const DdsBridge&) = delete;

  struct Published {
    std::string topic, dds_name, dds_type;
    DdsQos qos = DdsQos::best_effort;
    int depth = 1;
  };
  /// The bridged topics: tern topic, DDS topic name (rt/...), DDS type name, QoS and depth.
  std::vector<Published> published() const;
  /// The services served, by their ROS names ("tern/add_waypoint", "tern/status", and each
  /// instance's parameter services, "tern/filter/set_parameters"), sorted.
  std::vector<std::string> services() const;
  /// Answers one request to `service` (a name services() lists) as if it came from the wire,
  /// without DDS traffic: `request` is the serialized request (CDR with its 4-byte encapsulation
  /// header, as a DATA submessage carries it), decoded by the service's type and handled as a
  /// client's request is (the host's thread-safe API; a mission edit or parameter change queued
  /// for the next tick). Returns the reply serialized the same way, or nullopt when the bytes do
  /// not decode as the request type (a sample the wire drops). Throws DdsError for an unknown
  /// service. For tests and tests/fuzz/fuzz_dds_request.
  std::optional<std::vector<std::uint8_t>> answer(const std::string& service, const std::vector<std::uint8_t>& request);
  /// Samples written so far on a tern topic (0 for an unknown one).
  std::uint64_t samples_written(const std::string& topic) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One parameter as the vehicle reports it.
struct DdsParam {
  std::string name;  ///< "instance.param"
  ParamValue value, default_value;
  std::string unit, description;
  double min = 0, max = 0;
  std::vector<std::string> choices;
  std::uint32_t size = 0;
  bool read_only = false;  ///< start-only: changes between flights only
};

struct DdsStatus {
  std::string mission, config_file;
  bool flying = false;
  double flight_time = 0;  ///< s
  std::string phase;
  std::uint32_t flights = 0;
  std::vector<std::pair<std::string, std::string>> topics;  ///< DDS topic name, DDS type name
  std::vector<DdsQos> qos;                                  ///< of each topic
};

/// The ground side (the `tern` command's topics/echo/param/mission subcommands): a participant
/// on the same domain, namespace and interfaces as the vehicle. Each call waits until the
/// vehicle's service has matched, then for the reply; throws DdsError "no vehicle answered on
/// domain D, namespace N within T s" on timeout (for a change that was sent: it may have been
/// applied, how to check, and the request id to repeat it with), and DdsError with the vehicle's
/// message when a request is refused.
class DdsClient {
 public:
  explicit DdsClient(const DdsOptions& options, std::chrono::milliseconds timeout = std::chrono::seconds(3));
  ~DdsClient();
  DdsClient(const DdsClient&) = delete;
  DdsClient& operator=(const DdsClient&) = delete;

  /// The id of the next request (default: a fresh random one per request). A vehicle answers a
  /// repeated id with its first answer and does not apply it again: repeat a request that timed
  /// out with the id its error message gives.
  void set_request_id(std::uint64_t id);

  DdsStatus status();
  /// The vehicle's ROS 2 nodes with parameters (its instances), from ros_discovery_info.
  std::vector<std::string> nodes();
  /// Parameters through rcl_interfaces (list_parameters, get_parameters, describe_parameters,
  /// set_parameters of node /<namespace>/<instance>), as `ros2 param` does.
  std::vector<DdsParam> param_list(const std::string& prefix = "");
  DdsParam param_get(const std::string& name);
  /// Throws DdsError with the vehicle's reason when the value is refused (unknown, type, range).
  void param_set(const std::string& name, const ParamValue& value);
  /// Returns the path written on the vehicle: `filename` relative to the first directory the
  /// vehicle allows (or absolute inside one); an existing file only with `overwrite`.
  std::string param_save(const std::string& filename, bool overwrite = false);
  /// ROSplane's AddWaypoint: w (NED m or lat/lon/alt), chi_d, use_chi, Va_d, lla; set_current
  /// starts a new list with this waypoint; publish_now republishes the list immediately. An item
  /// with a type (loiter, return_home, land) goes through tern's add_mission_item instead.
  void mission_add(const msg::Waypoint& wp, bool set_current = false, bool publish_now = true);
  void mission_clear();
  void mission_load(const std::string& filename);
  /// The vehicle's current waypoint list, one waypoint per line.
  std::string mission_print();
  /// The operator's go-around (service `go_around`, std_srvs/Trigger): taken on the final approach
  /// or in the flare; DdsError with the vehicle's reason otherwise (the phase). Returns its answer.
  std::string go_around();
  /// Asks the vehicle to publish tern topic `topic` (e.g. truth, imu) from now on, at most
  /// `rate` Hz (0: every message). Returns "rt/<ns>/<topic> <DDS type>"; DdsError when the
  /// vehicle has no such topic or no DDS type for it.
  std::string bridge_topic(const std::string& topic, double rate = 0);
  /// Calls on_sample with each sample of a bridged topic (a tern topic the vehicle does not
  /// publish yet is asked for with bridge_topic) rendered as "field: value" lines, until
  /// on_sample returns false; throws DdsError when no sample arrives within the timeout.
  void echo(const std::string& topic, const std::function<bool(const std::string&)>& on_sample);

 private:
  std::string param_ns(const std::string& node) const;
  /// {instance, param} of "instance.param"; DdsError when the vehicle has no such instance.
  std::pair<std::string, std::string> known_node(const std::string& qualified);
  std::vector<DdsParam> describe(const std::string& node, const std::vector<std::string>& names);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Gives the MCAP flight log its ROS-typed channels (core/formats/ros/ros_channels.hpp): ROSplane's
/// profile's topics in their ROS types, encoded by this bridge's conversions. Call once at start-up.
void register_dds_mcap_channels();

}  // namespace tern::core
