// fuzz_dds_request: libFuzzer target for the DDS bridge's request handlers
// (core/apps/dds/include/dds_bridge.hpp DdsBridge::answer): a request's bytes decoded by the
// service's generated type (fastddsgen on Fast CDR, refusing what it cannot decode:
// src/decoding_type.hpp), then handled as a client's request is: add_waypoint, add_mission_item,
// clear_waypoints, print_waypoints, go_around, load_mission_from_file, param_save, bridge_topic,
// status, and each instance's rcl_interfaces parameter services (list, get, set, set atomically,
// describe, types). Its host is built once from the test plugins (tests/plugins), with a bridge on
// loopback-only DDS domain 229 (nothing else of tern's uses it); no DDS traffic is needed.
//
// The input is the service's ROS name, a NUL, then the serialized request (CDR with its 4-byte
// encapsulation header, as a DATA submessage carries it): "tern/filter/set_parameters\0\0\1\0\0...".
//
// Promised, whatever comes: no crash, no exception out of answer() but DdsError for a service
// that does not exist, bounded memory; bytes that do not decode are refused (no reply); every reply
// serialized (its encapsulation header first); a reply of the {success, message} services decodes,
// and a refusal's message is one printable line of at most 1000 characters (a client prints it).
// Mission edits and parameter changes an input queued are flown off in a flight of as many ticks,
// and param_save's files go with the flight's run directory, so that every input meets the same host.
// Inputs naming `fail_mode` are skipped: the test plugins' deliberate failures (a SIGSEGV, an
// endless loop: tests/plugins/misbehave.hpp) would be found, and are no finding.
//
// Seeds: `TERN_FUZZ_WRITE_SEEDS=DIR build-fuzz/bin/fuzz_dds_request -runs=0` writes a request of
// each service as a client sends it (the generated types' own serialisation) into DIR
// (tests/fuzz/corpus/fuzz_dds_request).
#include <algorithm>
#include <cstdint>
#include <limits>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "dds_bridge.hpp"
#include "decoding_type.hpp"
#include "flight/host.hpp"
#include "fuzz_host.hpp"
#include "rcl_interfaces/srv/ParametersPubSubTypes.h"
#include "rosplane_msgs/srv/AddWaypointPubSubTypes.h"
#include "std_srvs/srv/TriggerPubSubTypes.h"
#include "tern_msgs/srv/ServicesPubSubTypes.h"

using namespace tern::core;
namespace fs = std::filesystem;

namespace {

struct World {
  std::unique_ptr<Host> host;
  std::unique_ptr<DdsBridge> bridge;
  fs::path runs;
};

World& world() {
  static World w = [] {
    auto built = tern::fuzz::test_plugin_host("dds_request_fuzz");
    World made;
    made.host = std::move(built.host);
    made.runs = built.runs;
    DdsOptions d = parse_dds_options(YAML::Node(), built.config);
    d.enabled = true;
    d.domain = 229;
    made.bridge = std::make_unique<DdsBridge>(*made.host, d);
    fs::create_directories(made.runs);  // where param_save may write
    return made;
  }();
  return w;
}

bool verbose() { return std::getenv("TERN_FUZZ_VERBOSE") != nullptr; }

/// The services whose reply is {boolean success; string message} (std_srvs/Trigger's layout).
bool success_message_reply(const std::string& service) {
  static const std::set<std::string> names = {"add_waypoint", "add_mission_item",       "clear_waypoints", "print_waypoints",
                                              "go_around",    "load_mission_from_file", "param_save",      "bridge_topic"};
  const auto slash = service.rfind('/');
  return names.count(service.substr(slash == std::string::npos ? 0 : slash + 1)) > 0;
}

void check_reply(const std::string& service, const std::vector<std::uint8_t>& reply) {
  if (reply.size() < 4 || reply[0] != 0) __builtin_trap();  // CDR: the encapsulation header first
  if (!success_message_reply(service)) return;
  tern::core::ddsi::Decoding<std_srvs::srv::Trigger_ResponsePubSubType> type;
  eprosima::fastrtps::rtps::SerializedPayload_t p(static_cast<std::uint32_t>(reply.size()));
  std::memcpy(p.data, reply.data(), reply.size());
  p.length = static_cast<std::uint32_t>(reply.size());
  std_srvs::srv::Trigger_Response r;
  if (!type.deserialize(&p, &r)) __builtin_trap();
  if (verbose()) std::fprintf(stderr, "%s: %s %s\n", service.c_str(), r.success() ? "success" : "refused", r.message().c_str());
  if (r.success()) return;
  const std::string& m = r.message();
  if (m.empty() || m.size() > 1000) __builtin_trap();
  for (const char c : m)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) __builtin_trap();  // one printable line
}

/// One seed: the service's name, a NUL, the request as the generated type serializes it.
template <class PubSub>
void seed(const fs::path& dir, const std::string& file, const std::string& service, typename PubSub::type request) {
  PubSub type;
  eprosima::fastrtps::rtps::SerializedPayload_t p(type.getSerializedSizeProvider(&request)());
  if (!type.serialize(&request, &p)) __builtin_trap();
  std::ofstream out(dir / file, std::ios::binary);
  out << service << '\0';
  out.write(reinterpret_cast<const char*>(p.data), p.length);
}

rcl_interfaces::msg::Parameter parameter(const std::string& name, double value) {
  rcl_interfaces::msg::Parameter p;
  p.name(name);
  p.value().type(3);  // PARAMETER_DOUBLE
  p.value().double_value(value);
  return p;
}

void write_seeds(const fs::path& dir) {
  namespace rs = rcl_interfaces::srv;
  namespace ts = tern_msgs::srv;
  fs::create_directories(dir);
  rosplane_msgs::srv::AddWaypoint_Request wp;
  wp.w({100.0F, -50.0F, -40.0F});
  wp.va_d(18.0F);
  seed<rosplane_msgs::srv::AddWaypoint_RequestPubSubType>(dir, "add_waypoint.bin", "tern/add_waypoint", wp);
  wp.chi_d(std::numeric_limits<float>::quiet_NaN());
  wp.use_chi(true);
  seed<rosplane_msgs::srv::AddWaypoint_RequestPubSubType>(dir, "add_waypoint_nan.bin", "tern/add_waypoint", wp);
  ts::MissionAddItem_Request item;
  item.item().w({0.0, 300.0, -50.0});
  item.item().Va_d(17.0);
  item.item().type(1);  // loiter
  item.item().loiter_radius(60.0);
  item.item().loiter_turns(2.0);
  seed<ts::MissionAddItem_RequestPubSubType>(dir, "add_mission_item.bin", "tern/add_mission_item", item);
  for (const char* s : {"clear_waypoints", "print_waypoints", "go_around", "status"})
    seed<std_srvs::srv::Trigger_RequestPubSubType>(dir, std::string(s) + ".bin", std::string("tern/") + s, {});
  ts::MissionLoad_Request load;
  load.filename("dds_request.yaml");
  seed<ts::MissionLoad_RequestPubSubType>(dir, "load_mission_from_file.bin", "tern/load_mission_from_file", load);
  load.filename("../../../../../../etc/passwd");
  seed<ts::MissionLoad_RequestPubSubType>(dir, "load_mission_outside.bin", "tern/load_mission_from_file", load);
  ts::ParamSave_Request save;
  save.filename("saved_params.yaml");
  seed<ts::ParamSave_RequestPubSubType>(dir, "param_save.bin", "tern/param_save", save);
  ts::BridgeTopic_Request topic;
  topic.topic("imu");
  topic.rate(10);
  seed<ts::BridgeTopic_RequestPubSubType>(dir, "bridge_topic.bin", "tern/bridge_topic", topic);
  rs::ListParameters_Request list;
  seed<rs::ListParameters_RequestPubSubType>(dir, "list_parameters.bin", "tern/filter/list_parameters", list);
  rs::GetParameters_Request get;
  get.names({"valid", "log_every", "nope"});
  seed<rs::GetParameters_RequestPubSubType>(dir, "get_parameters.bin", "tern/filter/get_parameters", get);
  rs::DescribeParameters_Request describe;
  describe.names({"kp", "h_target"});
  seed<rs::DescribeParameters_RequestPubSubType>(dir, "describe_parameters.bin", "tern/ctl/describe_parameters", describe);
  rs::GetParameterTypes_Request types;
  types.names({"climb_gain", "noise"});
  seed<rs::GetParameterTypes_RequestPubSubType>(dir, "get_parameter_types.bin", "tern/sensor/get_parameter_types", types);
  rs::SetParameters_Request set;
  set.parameters({parameter("kp", 0.5), parameter("h_target", 1e308)});
  seed<rs::SetParameters_RequestPubSubType>(dir, "set_parameters.bin", "tern/ctl/set_parameters", set);
  rs::SetParametersAtomically_Request atomic;
  atomic.parameters({parameter("climb_gain", 0.2), parameter("noise", -1)});
  seed<rs::SetParametersAtomically_RequestPubSubType>(dir, "set_parameters_atomically.bin", "tern/sensor/set_parameters_atomically",
                                                      atomic);
}

}  // namespace

// Fast DDS 2.9 deletes its StatisticsReaderImpl (64 bytes) through RTPSReader's destructor with a
// 56-byte size whenever a DataReader goes (at exit here): the library's own mismatch, kept out as for
// the dds tests (tests/sanitizers/README.md); every other check stays on.
extern "C" const char* __asan_default_options() { return "new_delete_type_mismatch=0"; }

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("TERN_FUZZ_WRITE_SEEDS")) write_seeds(dir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static constexpr char kSkipped[] = "fail_mode";
  if (std::search(data, data + size, kSkipped, kSkipped + sizeof kSkipped - 1) != data + size) return 0;
  World& w = world();
  const auto* nul = static_cast<const std::uint8_t*>(std::memchr(data, 0, size));
  if (nul == nullptr) return 0;
  const std::string service(reinterpret_cast<const char*>(data), static_cast<std::size_t>(nul - data));
  const std::vector<std::uint8_t> request(nul + 1, data + size);
  try {
    if (const auto reply = w.bridge->answer(service, request)) check_reply(service, *reply);
  } catch (const DdsError& e) {
    tern::fuzz::note(e);
    if (std::string(e.what()).find("no service") == std::string::npos) __builtin_trap();
  }
  // what the input queued (mission edits, parameter changes) flown off, one per tick; the run
  // directory (the flight's log, param_save's files) removed
  const std::size_t n = w.host->queued_mission_edits();
  if (n > RemoteQueue::kMaxQueued) __builtin_trap();
  const bool changes = service.find("set_parameters") != std::string::npos || service.find("param_save") != std::string::npos;
  if (n == 0 && !changes) return 0;
  w.host->set_duration(static_cast<double>(n + 1) * tern::to_seconds(w.host->base_period()));
  w.host->fly();
  std::error_code ec;
  fs::remove_all(w.runs, ec);
  fs::create_directories(w.runs, ec);  // where param_save may write (the run directories' parent)
  return 0;
}
