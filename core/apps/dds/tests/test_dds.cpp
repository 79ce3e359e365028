// DDS bridge tests: a Host flying the host's test plugins, bridged over Fast DDS between
// loopback-only participants of this process (one DDS domain per test case).
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <dirent.h>

#include <fstream>
#include <regex>
#include <set>
#include <thread>

#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "dds_bridge.hpp"
#include "dds_internal.hpp"
#include "rosplane_msgs/msg/ControllerCommandsPubSubTypes.h"
#include "rosplane_msgs/msg/ControllerInternalsPubSubTypes.h"
#include "rosplane_msgs/msg/CurrentPathPubSubTypes.h"
#include "rosplane_msgs/msg/StatePubSubTypes.h"
#include "rosplane_msgs/msg/WaypointPubSubTypes.h"
#include "rosplane_msgs/srv/AddWaypointPubSubTypes.h"
#include "rosflight_msgs/msg/CommandPubSubTypes.h"
#include "rosgraph_msgs/msg/ClockPubSubTypes.h"
#include "sensor_msgs/msg/ImuPubSubTypes.h"
#include "rcl_convert.hpp"
#include "ros_graph.hpp"
#include "rcl_interfaces/msg/ParameterEventPubSubTypes.h"
#include "rcl_interfaces/srv/ParametersPubSubTypes.h"
#include "test_util.hpp"

using namespace tern::core;
namespace fdds = eprosima::fastdds::dds;

namespace {

DdsOptions options_on(std::uint32_t domain) {
  DdsOptions o = parse_dds_options(YAML::Node(), "none.yaml");
  o.enabled = true;
  o.domain = domain;
  REQUIRE(o.loopback_only());
  return o;
}

/// A host flying the standard test flight, paced to wall time so that requests arrive mid-flight.
struct Flight {
  Flight(const std::string& name, double duration, const std::string& top_extra = "") {
    HostOptions o;
    o.quiet = true;
    o.realtime = true;
    o.log_dir = test_dir() / name;
    std::string cfg = base_config("", top_extra);
    cfg.replace(cfg.find("duration: 2"), 11, "duration: " + std::to_string(duration));
    host = std::make_unique<Host>(load_config(write_file(name + ".yaml", cfg)), o);
    host->build();
  }
  void start() {
    thread = std::thread([this] { result = host->fly(); });
    REQUIRE(ddsi::wait_until([&] { return host->flying(); }, std::chrono::seconds(5)));
  }
  FlightResult finish() {
    thread.join();
    return result;
  }
  ~Flight() {
    if (thread.joinable()) thread.join();  // a failed check mid-flight: let the flight end
  }
  std::unique_ptr<Host> host;
  std::thread thread;
  FlightResult result;
};

bool reader_matched(fdds::DataReader* r) {
  fdds::SubscriptionMatchedStatus s;
  r->get_subscription_matched_status(s);
  return s.current_count > 0;
}

bool writer_matched(fdds::DataWriter* w) {
  fdds::PublicationMatchedStatus s;
  w->get_publication_matched_status(s);
  return s.current_count > 0;
}

/// A reader of rt/tern/estimated_state as ROSplane's nodes subscribe (rclcpp's
/// create_subscription(topic, 10): reliable, volatile, keep-last 10).
fdds::DataReader* rosplane_state_reader(fdds::DomainParticipant* p, fdds::Subscriber* sub) {
  auto* r = sub->create_datareader(ddsi::make_topic<rosplane_msgs::msg::StatePubSubType>(p, "rt/tern/estimated_state"),
                                   ddsi::reader_qos(DdsQos::reliable));
  REQUIRE(r != nullptr);
  return r;
}

/// The sockets of this process and their local IPv4 addresses (hex, as in /proc/net/udp).
std::vector<std::string> socket_addresses() {
  std::set<std::string> inodes;
  DIR* d = opendir("/proc/self/fd");
  REQUIRE(d != nullptr);
  while (dirent* e = readdir(d)) {
    std::error_code ec;
    const auto target = fs::read_symlink(fs::path("/proc/self/fd") / e->d_name, ec).string();
    if (!ec && target.rfind("socket:[", 0) == 0) inodes.insert(target.substr(8, target.size() - 9));
  }
  closedir(d);
  std::vector<std::string> out;
  for (const char* table : {"/proc/net/udp", "/proc/net/tcp", "/proc/net/udp6", "/proc/net/tcp6"}) {
    std::ifstream in(table);
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
      std::istringstream ss(line);
      std::string sl, local, remote, st, txrx, trtm, retr, uid, timeout, inode;
      ss >> sl >> local >> remote >> st >> txrx >> trtm >> retr >> uid >> timeout >> inode;
      if (inodes.count(inode)) out.push_back(std::string(table) + " " + local);
    }
  }
  return out;
}

/// Fields of a ROS .msg/.srv section: "type name" per line, constants and comments dropped.
std::vector<std::pair<std::string, std::string>> msg_fields(const std::string& text) {
  std::vector<std::pair<std::string, std::string>> out;
  for (auto line : lines(text)) {
    line = line.substr(0, line.find('#'));
    std::istringstream ss(line);
    std::string type, name;
    if (!(ss >> type >> name) || name.find('=') != std::string::npos || line.find('=') != std::string::npos) continue;
    out.emplace_back(type, name);
  }
  return out;
}

/// Members of `struct name { ... };` in an IDL file as ROS types ("float32[3] w" -> ("float32[3]", "w")).
std::vector<std::pair<std::string, std::string>> idl_fields(const std::string& text, const std::string& name) {
  static const std::map<std::string, std::string> ros = {{"float", "float32"},
                                                         {"double", "float64"},
                                                         {"boolean", "bool"},
                                                         {"uint8", "uint8"},
                                                         {"int8", "int8"},
                                                         {"uint16", "uint16"},
                                                         {"int16", "int16"},
                                                         {"uint32", "uint32"},
                                                         {"int32", "int32"},
                                                         {"int64", "int64"},
                                                         {"string", "string"},
                                                         {"std_msgs::msg::Header", "std_msgs/Header"},
                                                         {"geometry_msgs::msg::Quaternion", "geometry_msgs/Quaternion"},
                                                         {"geometry_msgs::msg::Vector3", "geometry_msgs/Vector3"},
                                                         {"builtin_interfaces::msg::Time", "builtin_interfaces/Time"}};
  const auto at = text.find("struct " + name + " {");
  REQUIRE_MESSAGE(at != std::string::npos, name);
  const auto end = text.find("};", at);
  std::vector<std::pair<std::string, std::string>> out;
  const std::regex member(R"(^\s*([A-Za-z_:0-9]+)\s+([A-Za-z_0-9]+)(\[(\d+)\])?;)");
  for (const auto& l : lines(text.substr(at, end - at))) {
    std::smatch m;
    if (!std::regex_search(l, m, member)) continue;
    const auto it = ros.find(m[1]);
    REQUIRE_MESSAGE(it != ros.end(), m[1]);
    out.emplace_back(it->second + (m[3].matched ? "[" + m[4].str() + "]" : ""), m[2]);
  }
  return out;
}

}  // namespace

TEST_CASE("dds: options: defaults are loopback-only; bad keys and values name file, line and field") {
  const DdsOptions d = parse_dds_options(YAML::Node(), "m.yaml");
  CHECK_FALSE(d.enabled);
  CHECK(d.loopback_only());
  CHECK(d.ns == "tern");
  // ROSplane's profile (13 topics), then tern's own names state, waypoints, actuators
  REQUIRE(d.topics.size() == 16);
  CHECK(d.topics[0].topic == "state");
  CHECK(d.topics[0].name == "estimated_state");
  CHECK(*d.topics[0].qos == DdsQos::reliable);
  CHECK(*d.topics[0].depth == 10);
  CHECK(d.topics[0].type == "rosplane_msgs/msg/State");
  CHECK(d.topics[13].name == "state");
  CHECK(d.time == DdsTime::automatic);
  CHECK(d.clock_rate == 100);
  CHECK_FALSE(d.topics_from_config);
  const fs::path f = write_file("dds_opts.yaml", "dds:\n  domian: 3\n");
  auto err = [&](const std::string& yaml) {
    const fs::path p = write_file("dds_opts.yaml", yaml);
    try {
      parse_dds_options(YAML::LoadFile(p.string())["dds"], p);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(err("dds:\n  domian: 3\n") == f.string() + ":2:3: dds: unknown key 'domian' (did you mean 'domain'?)");
  CHECK(err("dds:\n  domain: 300\n") == f.string() + ":2:11: dds.domain: 300 is outside [0, 232]");
  CHECK(err("dds:\n  interfaces: [eth0]\n").find("dds.interfaces[0]: 'eth0' is not an IPv4 address") != std::string::npos);
  CHECK(err("dds:\n  topics: [{topic: state, qos: fast}]\n").find("dds.topics[0].qos: 'fast' is not one of") != std::string::npos);
  CHECK(err("dds:\n  topics: [{topic: imu, depth: 0}]\n").find("dds.topics[0].depth: 0 is outside [1, 1000]") != std::string::npos);
  CHECK(err("dds:\n  topics: [{topic: imu, type: Imu}]\n").find("dds.topics[0].type: 'Imu' is not a ROS 2 message type") !=
        std::string::npos);
  CHECK(err("dds:\n  time: gps\n").find("dds.time: 'gps' is not one of auto, sim, wall") != std::string::npos);
  CHECK(err("dds:\n  clock_rate: -1\n").find("dds.clock_rate: -1 is outside [0, 10000]") != std::string::npos);
  const fs::path lean = write_file("dds_lean.yaml", "dds:\n  aliases: false\n  time: wall\n  clock_rate: 50\n");
  const DdsOptions lo = parse_dds_options(YAML::LoadFile(lean.string())["dds"], lean);
  CHECK(lo.topics.size() == 13);
  CHECK(lo.time == DdsTime::wall);
  CHECK(lo.clock_rate == 50);
  const fs::path ok = write_file("dds_ok.yaml",
                                 "dds:\n  enabled: true\n  domain: 7\n  namespace: /uav1/\n  interfaces: [127.0.0.1, 192.168.1.10]\n"
                                 "  topics: [state, {topic: truth, name: truth_state, rate: 10, qos: reliable}]\n");
  const DdsOptions o = parse_dds_options(YAML::LoadFile(ok.string())["dds"], ok);
  CHECK(o.enabled);
  CHECK(o.domain == 7);
  CHECK(o.ns == "uav1");
  CHECK_FALSE(o.loopback_only());
  REQUIRE(o.topics.size() == 2);
  CHECK(o.topics[1].name == "truth_state");
  CHECK(o.topics[1].rate == 10);
  CHECK(*o.topics[1].qos == DdsQos::reliable);
  CHECK_FALSE(o.read_only);
  // issue 20: telemetry only, and the directories file requests may use (relative to the config)
  const fs::path files =
      write_file("dds_files.yaml", "dds:\n  read_only: true\n  mission_dirs: [wp, /srv/missions]\n  param_dirs: [gains]\n");
  const DdsOptions fo = parse_dds_options(YAML::LoadFile(files.string())["dds"], files);
  CHECK(fo.read_only);
  CHECK(fo.mission_dirs == std::vector<fs::path>{test_dir() / "wp", "/srv/missions"});
  CHECK(fo.param_dirs == std::vector<fs::path>{test_dir() / "gains"});
  CHECK(err("dds:\n  mission_dirs: wp\n").find("dds.mission_dirs: expected a list of directories, got 'wp'") != std::string::npos);
  CHECK(err("dds:\n  read_only: maybe\n").find("dds.read_only: expected true or false, got 'maybe'") != std::string::npos);
}

TEST_CASE("dds: type names are ROS 2's and the fields follow ROSplane's .msg files in order") {
  CHECK(std::string(rosplane_msgs::msg::StatePubSubType().getName()) == "rosplane_msgs::msg::dds_::State_");
  CHECK(std::string(rosplane_msgs::msg::ControllerCommandsPubSubType().getName()) == "rosplane_msgs::msg::dds_::ControllerCommands_");
  CHECK(std::string(rosplane_msgs::msg::ControllerInternalsPubSubType().getName()) == "rosplane_msgs::msg::dds_::ControllerInternals_");
  CHECK(std::string(rosplane_msgs::msg::CurrentPathPubSubType().getName()) == "rosplane_msgs::msg::dds_::CurrentPath_");
  CHECK(std::string(rosplane_msgs::msg::WaypointPubSubType().getName()) == "rosplane_msgs::msg::dds_::Waypoint_");
  CHECK(std::string(rosplane_msgs::srv::AddWaypoint_RequestPubSubType().getName()) == "rosplane_msgs::srv::dds_::AddWaypoint_Request_");
  CHECK(std::string(rosplane_msgs::srv::AddWaypoint_ResponsePubSubType().getName()) == "rosplane_msgs::srv::dds_::AddWaypoint_Response_");
  const fs::path idl = TERN_DDS_IDL_DIR, ref = TERN_ROSPLANE_MSG_DIR;
  for (const std::string m : {"State", "ControllerCommands", "ControllerInternals", "CurrentPath", "Waypoint"}) {
    const auto want = msg_fields(read_file(ref / "rosplane_msgs/msg" / (m + ".msg")));
    const auto got = idl_fields(read_file(idl / "rosplane_msgs/msg" / (m + ".idl")), m);
    REQUIRE(want.size() > 3);
    CHECK_MESSAGE(got == want, m);
  }
  const std::string srv = read_file(ref / "rosplane_msgs/srv/AddWaypoint.srv");
  const auto sep = srv.find("---");
  const std::string srv_idl = read_file(idl / "rosplane_msgs/srv/AddWaypoint.idl");
  CHECK(idl_fields(srv_idl, "AddWaypoint_Request") == msg_fields(srv.substr(0, sep)));
  CHECK(idl_fields(srv_idl, "AddWaypoint_Response") == msg_fields(srv.substr(sep + 3)));
}

TEST_CASE("dds: rosflight_io's, sensor_msgs' and /clock's IDL follow their .msg files in order") {
  CHECK(std::string(rosflight_msgs::msg::CommandPubSubType().getName()) == "rosflight_msgs::msg::dds_::Command_");
  CHECK(std::string(sensor_msgs::msg::ImuPubSubType().getName()) == "sensor_msgs::msg::dds_::Imu_");
  CHECK(std::string(rosgraph_msgs::msg::ClockPubSubType().getName()) == "rosgraph_msgs::msg::dds_::Clock_");
  const fs::path idl = TERN_DDS_IDL_DIR, ref = TERN_ROSPLANE_MSG_DIR;
  const std::pair<const char*, const char*> msgs[] = {
      {"rosflight_msgs/msg", "Command"},    {"rosflight_msgs/msg", "Barometer"}, {"rosflight_msgs/msg", "Airspeed"},
      {"rosflight_msgs/msg", "Status"},     {"rosflight_msgs/msg", "GNSS"},      {"sensor_msgs/msg", "Imu"},
      {"sensor_msgs/msg", "MagneticField"}, {"geometry_msgs/msg", "Vector3"},    {"rosgraph_msgs/msg", "Clock"}};
  for (const auto& [dir, m] : msgs) {
    const std::string folder = dir;
    const fs::path msg_dir = folder.rfind("rosflight", 0) == 0 ? ref / dir : ref / "ros2_msgs" / dir;
    const auto want = msg_fields(read_file(msg_dir / (std::string(m) + ".msg")));
    const auto got = idl_fields(read_file(idl / dir / (std::string(m) + ".idl")), m);
    REQUIRE(!want.empty());
    CHECK_MESSAGE(got == want, m);
  }
}

TEST_CASE("dds: a reader receives `state` from a flying host; every socket is on loopback") {
  const DdsOptions opt = options_on(41);
  Flight f("dds_state", 1.5);
  DdsBridge bridge(*f.host, opt);
  // of the default set, the test flight has state, controller_internals, actuators and imu: in
  // ROSplane's names and, as aliases, tern's state and actuators
  std::vector<std::string> names;
  for (const auto& pb : bridge.published()) names.push_back(pb.dds_name + " " + pb.dds_type);
  CHECK(names == std::vector<std::string>{"rt/tern/estimated_state rosplane_msgs::msg::dds_::State_",
                                          "rt/tern/controller_internals rosplane_msgs::msg::dds_::ControllerInternals_",
                                          "rt/tern/command rosflight_msgs::msg::dds_::Command_",
                                          "rt/tern/imu/data sensor_msgs::msg::dds_::Imu_", "rt/tern/state rosplane_msgs::msg::dds_::State_",
                                          "rt/tern/actuators tern_msgs::msg::dds_::Actuators_"});

  auto* p = ddsi::make_participant(opt, "test reader");
  auto* sub = p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  auto* topic = ddsi::make_topic<rosplane_msgs::msg::StatePubSubType>(p, "rt/tern/state");
  auto* reader = sub->create_datareader(topic, ddsi::reader_qos(DdsQos::best_effort));
  REQUIRE(reader != nullptr);
  REQUIRE(ddsi::wait_until([&] { return reader_matched(reader); }, std::chrono::seconds(10)));
  // DDS on with the default config: nothing listens or sends on a non-loopback address
  const auto sockets = socket_addresses();
  CHECK(sockets.size() >= 4);  // two participants, each with metatraffic and user unicast sockets
  for (const auto& s : sockets) CHECK_MESSAGE(s.find(" 0100007F:") != std::string::npos, s);

  f.start();
  REQUIRE(reader->wait_for_unread_message(eprosima::fastrtps::Duration_t(5, 0)));
  rosplane_msgs::msg::State st;
  fdds::SampleInfo info;
  REQUIRE(reader->take_next_sample(&st, &info) == ReturnCode_t::RETCODE_OK);
  CHECK(info.valid_data);
  CHECK(st.va() == 15.0f);      // test_sensor's truth, passed through by test_filter
  CHECK(st.quat().w() == 1.0);  // identity attitude
  CHECK(st.header().stamp().sec() >= 0);
  const FlightResult r = f.finish();
  CHECK(r.ok);
  CHECK(bridge.samples_written("state") >= 100);  // 400 Hz over 1.5 s, every message by default
  ddsi::delete_participant(p);
}

TEST_CASE("dds: ROSplane profile: readers with ROSplane's QoS match; stamps are sim time; /clock advances with it") {
  const DdsOptions opt = options_on(211);
  Flight f("dds_profile", 2.0);
  DdsBridge bridge(*f.host, opt);
  auto* p = ddsi::make_participant(opt, "ros node");
  auto* sub = p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  auto* state = rosplane_state_reader(p, sub);
  // rclcpp's ClockQoS: best-effort, keep-last 1
  auto* clock =
      sub->create_datareader(ddsi::make_topic<rosgraph_msgs::msg::ClockPubSubType>(p, "rt/clock"), ddsi::reader_qos(DdsQos::best_effort));
  REQUIRE(clock != nullptr);
  REQUIRE(ddsi::wait_until([&] { return reader_matched(state) && reader_matched(clock); }, std::chrono::seconds(10)));
  fdds::RequestedIncompatibleQosStatus incompatible;
  state->get_requested_incompatible_qos_status(incompatible);
  CHECK(incompatible.total_count == 0);
  f.start();
  std::vector<double> clocks;
  rosplane_msgs::msg::State st;
  rosgraph_msgs::msg::Clock c;
  fdds::SampleInfo info;
  double last_state_stamp = -1;
  int states = 0;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(4);
  while (std::chrono::steady_clock::now() < end && f.host->flying()) {
    while (clock->take_next_sample(&c, &info) == ReturnCode_t::RETCODE_OK)
      if (info.valid_data) clocks.push_back(c.clock().sec() + c.clock().nanosec() * 1e-9);
    while (state->take_next_sample(&st, &info) == ReturnCode_t::RETCODE_OK)
      if (info.valid_data) {
        const double t = st.header().stamp().sec() + st.header().stamp().nanosec() * 1e-9;
        CHECK(t >= last_state_stamp);
        last_state_stamp = t;
        ++states;
      }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  REQUIRE(f.finish().ok);
  // 2 s of flight at 100 Hz: /clock from 0, 10 ms apart, in the same time as the stamps
  REQUIRE(clocks.size() >= 150);
  CHECK(clocks.front() < 0.5);
  CHECK(clocks.back() > 1.9);
  CHECK(clocks.back() <= 2.0 + 1e-9);
  for (std::size_t i = 1; i < clocks.size(); ++i) CHECK(clocks[i] > clocks[i - 1]);
  CHECK(states > 100);
  CHECK(last_state_stamp == doctest::Approx(clocks.back()).epsilon(0.05));
  ddsi::delete_participant(p);
}

TEST_CASE("dds: with wall time (a real FCU) stamps are UNIX time and there is no /clock") {
  DdsOptions opt = options_on(212);
  opt.time = DdsTime::wall;
  Flight f("dds_wall", 0.5);
  DdsBridge bridge(*f.host, opt);
  auto* p = ddsi::make_participant(opt, "ros node");
  auto* sub = p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  auto* state = rosplane_state_reader(p, sub);
  REQUIRE(ddsi::wait_until([&] { return reader_matched(state); }, std::chrono::seconds(10)));
  const double t0 = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  f.start();
  REQUIRE(state->wait_for_unread_message(eprosima::fastrtps::Duration_t(5, 0)));
  rosplane_msgs::msg::State st;
  fdds::SampleInfo info;
  REQUIRE(state->take_next_sample(&st, &info) == ReturnCode_t::RETCODE_OK);
  const double stamp = st.header().stamp().sec() + st.header().stamp().nanosec() * 1e-9;
  CHECK(stamp > t0 - 1.0);
  CHECK(stamp < t0 + 5.0);
  REQUIRE(f.finish().ok);
  for (const auto& pb : bridge.published()) CHECK(pb.dds_name != "rt/clock");
  CHECK(p->find_topic("rt/clock", eprosima::fastrtps::Duration_t(0, 0)) == nullptr);
  ddsi::delete_participant(p);
}

TEST_CASE("dds: parameters: set mid-flight takes effect at the next tick and is logged; bad values are refused") {
  const DdsOptions opt = options_on(42);
  Flight f("dds_params", 2.0);
  DdsBridge bridge(*f.host, opt);
  DdsClient client(opt, std::chrono::seconds(20));
  // between flights: list and get answer directly
  const auto all = client.param_list("ctl.");
  REQUIRE(all.size() == 6);  // test_controller: h_target, kp, tag, aileron, fail_mode, fail_at
  const DdsParam kp = client.param_get("ctl.kp");
  CHECK(std::get<double>(kp.value) == doctest::Approx(0.05));
  CHECK(kp.unit == "1/m");
  CHECK(kp.max == 10.0);
  f.start();
  REQUIRE(ddsi::wait_until([&] { return bridge.samples_written("state") > 10; }, std::chrono::seconds(20)));
  client.param_set("ctl.tag", 0.25);
  try {
    client.param_set("ctl.kp", 50.0);
    FAIL("out-of-range value accepted");
  } catch (const DdsError& e) {
    CHECK(std::string(e.what()) == "parameter 'ctl.kp': value 50 is outside the valid range [0, 10] 1/m");
  }
  CHECK_THROWS_WITH_AS(client.param_set("ctl.kq", 0.1), "unknown parameter 'ctl.kq' (did you mean 'ctl.kp'?)", DdsError);
  CHECK_THROWS_WITH_AS(client.param_get("ctrl.kp"), "unknown parameter 'ctrl.kp': the vehicle has no instance 'ctrl' (did you mean 'ctl'?)",
                       DdsError);
  CHECK_THROWS_AS(client.param_set("ctl.fail_mode", std::string("explode")), DdsError);
  // while flying, reads are answered from the flight thread
  REQUIRE(ddsi::wait_until([&] { return std::get<double>(client.param_get("ctl.tag").value) == 0.25; }, std::chrono::seconds(2)));
  CHECK(std::get<double>(client.param_get("ctl.kp").value) == doctest::Approx(0.05));
  const std::string saved = client.param_save("saved_params.yaml");
  const FlightResult r = f.finish();
  REQUIRE(r.ok);
  // params.csv: the change, stamped with the tick that applied it, source "dds"; kp never changed
  std::string row;
  for (const auto& l : lines(read_file(r.run_dir / "params.csv")))
    if (l.find(",ctl.tag,0.25,dds") != std::string::npos) row = l;
  REQUIRE(!row.empty());
  const double t_set = std::stod(row.substr(0, row.find(',')));
  CHECK(t_set > 0.0);
  for (const auto& l : lines(read_file(r.run_dir / "params.csv"))) CHECK(l.find("ctl.kp,50") == std::string::npos);
  // the controller uses it from that tick on (delta_e = tag)
  bool before = false, after = false;
  for (const auto& l : lines(read_file(r.run_dir / "topics" / "actuators.csv"))) {
    if (l.empty() || !std::isdigit(static_cast<unsigned char>(l[0]))) continue;
    const double t = std::stod(l.substr(0, l.find(',')));
    const bool tagged = l.find(",0.25,") != std::string::npos;
    if (t < t_set) before = before || tagged;
    if (t >= t_set + 0.0101) after = after || tagged;  // next 100 Hz step of ctl
  }
  CHECK_FALSE(before);
  CHECK(after);
  // the saved file is a ROS 2 style parameter file the host can load back
  CHECK(saved == (test_dir() / "dds_params" / "saved_params.yaml").string());  // the log directory
  const auto params = load_param_file(saved, "ctl", "test_controller");
  CHECK(params.at("tag").node.as<double>() == 0.25);
  CHECK(params.at("kp").node.as<double>() == 0.05);
}

TEST_CASE("dds: mission add and clear over DDS reach the mission_edit topic") {
  DdsOptions opt = options_on(43);
  opt.topics[0].rate = 20;  // estimated_state at 20 Hz (it is published at 400 Hz)
  // 8 s: long enough for the client to discover the vehicle's services (a node per instance) in flight,
  // on a loaded machine too (4 s ended before the status call once in make test on 2 cores)
  Flight f("dds_mission", 8.0, "phases: {takeoff: ctl, climb: ctl, cruise: ctl}\nphase_machine: {preflight: false}\n");
  DdsBridge bridge(*f.host, opt);
  DdsClient client(opt, std::chrono::seconds(20));
  f.start();
  tern::msg::Waypoint wp;
  wp.w = Eigen::Vector3d(100.0, -50.0, -40.0);
  wp.Va_d = 18.0;
  wp.chi_d = 0.5;
  wp.use_chi = true;
  client.mission_clear();
  client.mission_add(wp, false, true);
  wp.Va_d = -1;
  CHECK_THROWS_WITH_AS(client.mission_add(wp), doctest::Contains("va_d > 0"), DdsError);
  CHECK_THROWS_WITH_AS(client.mission_load("no_such_mission.yaml"), doctest::Contains("no such file on the vehicle"), DdsError);
  CHECK_THROWS_WITH_AS(client.mission_print(), doctest::Contains("no waypoint list published yet"), DdsError);
  const DdsStatus st = client.status();
  CHECK(st.mission == "hostcheck");
  CHECK(st.flying);
  // estimated_state, controller_internals, command, imu/data, flight_phase, and tern's state, actuators
  REQUIRE(st.topics.size() == 7);
  CHECK(st.topics[4].first == "rt/tern/flight_phase");
  CHECK(st.qos[4] == DdsQos::transient_local);
  CHECK(st.qos[0] == DdsQos::reliable);
  CHECK(st.topics[0] == std::pair<std::string, std::string>("rt/tern/estimated_state", "rosplane_msgs::msg::dds_::State_"));
  CHECK(st.topics[5] == std::pair<std::string, std::string>("rt/tern/state", "rosplane_msgs::msg::dds_::State_"));
  std::string echoed;
  client.echo("state", [&](const std::string& s) {
    echoed = s;
    return false;
  });
  CHECK(echoed.find("va: 15\n") != std::string::npos);
  // flight_phase is transient-local: echo gets the last phase at once, even if it does not change
  std::string phase;
  client.echo("flight_phase", [&](const std::string& s) {
    phase = s;
    return false;
  });
  CHECK(phase.find("phase_name: '") != std::string::npos);
  const FlightResult r = f.finish();
  REQUIRE(r.ok);
  CHECK(bridge.samples_written("state") >= 159);  // 20 Hz over 8 s of flight time: 161
  CHECK(bridge.samples_written("state") <= 161);
  CHECK(bridge.samples_written("controller_internals") >= 800);  // no limit: every 100 Hz step
  const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
  CHECK(s["instances"]["filter"]["mission_edits"] == 2.0);
  CHECK(s["instances"]["filter"]["last_edit_id"] == 2.0);
  const auto rows = lines(read_file(r.run_dir / "topics" / "mission_edit.csv"));
  REQUIRE(rows.size() == 3);
  CHECK(rows[1].find(",1,1,0,1,") != std::string::npos);  // id 1: clear
  CHECK(rows[2].find(",2,0,0,1,") != std::string::npos);  // id 2: add, set_current false, publish_now true
  // the waypoint as the planner received it (the last edit on the topic)
  const auto* src = f.host->topic_source("mission_edit");
  REQUIRE(src != nullptr);
  const auto& e = *static_cast<const tern::msg::MissionEdit*>(src->data());
  CHECK(e.id == 2);
  CHECK(e.waypoint.w == Eigen::Vector3d(100.0, -50.0, -40.0));
  CHECK(e.waypoint.Va_d == 18.0);
  CHECK(e.waypoint.chi_d == 0.5);
  CHECK(e.waypoint.use_chi);
  CHECK_FALSE(e.waypoint.lla);
}

TEST_CASE("dds: replies reach the client that asked (sample identity), with two clients asking at once") {
  const DdsOptions opt = options_on(45);
  Flight f("dds_two_clients", 1.0);
  DdsBridge bridge(*f.host, opt);
  DdsClient a(opt, std::chrono::seconds(20)), b(opt, std::chrono::seconds(20));
  std::vector<std::string> got_a, got_b;
  std::string err_a, err_b;
  std::thread ta([&] {
    try {
      for (int i = 0; i < 20; ++i) got_a.push_back(a.param_get("ctl.kp").name);
    } catch (const std::exception& e) {
      err_a = e.what();
    }
  });
  try {
    for (int i = 0; i < 20; ++i) got_b.push_back(b.param_get("sensor.noise").name);
  } catch (const std::exception& e) {
    err_b = e.what();
  }
  ta.join();
  CHECK(err_a == "");
  CHECK(err_b == "");
  CHECK(got_a == std::vector<std::string>(20, "ctl.kp"));
  CHECK(got_b == std::vector<std::string>(20, "sensor.noise"));
}

TEST_CASE("dds: a client with no vehicle on its domain gets a clear timeout error") {
  DdsClient client(options_on(44), std::chrono::milliseconds(300));
  CHECK_THROWS_WITH_AS(client.param_set("ctl.kp", 0.1),
                       "no vehicle announced its nodes (ros_discovery_info) on DDS domain 44, namespace 'tern' within 0.3 s", DdsError);
}

TEST_CASE("dds: file requests from the network stay inside the allowed directories (issue 20)") {
  const DdsOptions opt = options_on(46);
  Flight f("dds_files", 1.0);
  fs::create_directories(test_dir() / "dds_files");  // the log directory: param_save's default
  DdsBridge bridge(*f.host, opt);
  DdsClient client(opt, std::chrono::seconds(20));
  CHECK_THROWS_WITH_AS(client.mission_load("../../../../etc/shadow"),
                       doctest::Contains("load_mission_from_file: refused '../../../../etc/shadow': '..' is not allowed"), DdsError);
  CHECK_THROWS_WITH_AS(client.mission_load("/etc/shadow"), "load_mission_from_file: refused '/etc/shadow': only .yaml or .yml files",
                       DdsError);
  CHECK_THROWS_WITH_AS(client.param_save("/tmp/tern_params.yaml"),
                       doctest::Contains("param_save: refused '/tmp/tern_params.yaml': outside the allowed directories"), DdsError);
  const std::string path = client.param_save("p.yaml");
  CHECK(path == (test_dir() / "dds_files" / "p.yaml").string());
  CHECK_THROWS_WITH_AS(client.param_save("p.yaml"), ("param_save: refused: " + path + " exists (ask to overwrite it: --overwrite)").c_str(),
                       DdsError);
  CHECK(client.param_save("p.yaml", true) == path);
}

TEST_CASE("dds: read_only serves telemetry and status, and no parameter, mission or file service") {
  DdsOptions opt = options_on(47);
  opt.read_only = true;
  Flight f("dds_read_only", 1.0);
  DdsBridge bridge(*f.host, opt);
  DdsClient client(opt, std::chrono::seconds(20));
  CHECK(client.status().mission == "hostcheck");
  // long enough to find the vehicle's nodes under load (else the error is about discovery)
  DdsClient quick(opt, std::chrono::seconds(5));
  CHECK_THROWS_WITH_AS(quick.param_set("ctl.kp", 0.1), doctest::Contains("no vehicle answered 'set_parameters'"), DdsError);
  CHECK_THROWS_WITH_AS(quick.mission_load("m.yaml"), doctest::Contains("no vehicle answered 'load_mission_from_file'"), DdsError);
}

TEST_CASE("dds: a repeated request id gets the first answer and is applied once (issue 20: a retried add added twice)") {
  DdsOptions opt = options_on(48);
  Flight f("dds_request_ids", 4.0, "phases: {takeoff: ctl, climb: ctl, cruise: ctl}\nphase_machine: {preflight: false}\n");
  DdsBridge bridge(*f.host, opt);
  DdsClient client(opt, std::chrono::seconds(20)), retry(opt, std::chrono::seconds(20));
  f.start();
  tern::msg::Waypoint wp;
  wp.w = Eigen::Vector3d(100.0, -50.0, -40.0);
  wp.Va_d = 18.0;
  client.set_request_id(1234);
  client.mission_add(wp);
  retry.set_request_id(1234);  // another process repeating the request after a time-out
  retry.mission_add(wp);
  client.mission_add(wp);  // a new request (a fresh id): applied
  const FlightResult r = f.finish();
  REQUIRE(r.ok);
  const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
  CHECK(s["instances"]["filter"]["mission_edits"] == 2.0);
  CHECK(s["instances"]["filter"]["last_edit_id"] == 2.0);
}

TEST_CASE("dds: a request sent but not answered says it may have been applied, how to check and the id to repeat it with") {
  const DdsOptions opt = options_on(49);
  // a vehicle that takes requests and never answers
  auto* p = ddsi::make_participant(opt, "mute");
  auto* pub = p->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  auto* sub = p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  using namespace rcl_interfaces::srv;
  auto* rw = pub->create_datawriter(ddsi::make_topic<SetParameters_ResponsePubSubType>(p, ddsi::reply_topic("tern/ctl", "set_parameters")),
                                    ddsi::service_writer_qos());
  auto* rr = sub->create_datareader(ddsi::make_topic<SetParameters_RequestPubSubType>(p, ddsi::request_topic("tern/ctl", "set_parameters")),
                                    ddsi::service_reader_qos());
  REQUIRE((rw != nullptr && rr != nullptr));
  ddsi::RosGraph graph(p, pub);
  graph.announce({{"/tern", "ctl", {rr->guid()}, {rw->guid()}}});
  {
    DdsClient client(opt, std::chrono::milliseconds(1500));
    client.set_request_id(77);
    CHECK_THROWS_WITH_AS(client.param_set("ctl.kp", 0.1),
                         "no vehicle answered 'set_parameters' on DDS domain 49, namespace 'tern' within 1.5 s: the request was sent and "
                         "may have been applied; check with `tern param get ctl.kp`, or repeat it with --request-id 77 (the vehicle "
                         "applies one id once)",
                         DdsError);
  }
  ddsi::delete_participant(p);
}

TEST_CASE("dds: a topic not bridged by default (imu in tern's type) is published when a client asks for it") {
  const DdsOptions opt = options_on(50);
  Flight f("dds_bridge_topic", 1.0);
  DdsBridge bridge(*f.host, opt);
  DdsClient client(opt, std::chrono::seconds(20));
  CHECK_THROWS_WITH_AS(client.bridge_topic("imux"), "bridge_topic: no instance publishes topic 'imux' (did you mean 'imu'?)", DdsError);
  f.start();
  std::string sample;
  client.echo("imu", [&](const std::string& s) {  // asks for it: not in the default set
    sample = s;
    return false;
  });
  CHECK(sample.find("header.stamp: ") != std::string::npos);
  CHECK(client.bridge_topic("imu") == "rt/tern/imu is already published");
  bool listed = false;
  for (const auto& pbl : bridge.published()) listed = listed || pbl.dds_name == "rt/tern/imu";
  CHECK(listed);
  REQUIRE(f.finish().ok);
}

namespace {
/// A ServiceClient of an instance's rcl_interfaces service, as `ros2 param` reaches it.
template <class ReqPS, class RespPS>
typename RespPS::type ros_call(fdds::DomainParticipant* p, fdds::Publisher* pub, fdds::Subscriber* sub, const std::string& node,
                               const std::string& service, const typename ReqPS::type& rq) {
  ddsi::ServiceClient<ReqPS, RespPS> c(p, pub, sub, "tern/" + node, service);
  typename RespPS::type r;
  REQUIRE(c.call(rq, r, std::chrono::seconds(20), ddsi::new_request_id()) == ddsi::CallResult::answered);
  return r;
}
}  // namespace

TEST_CASE("dds: each instance is a ROS 2 node serving rcl_interfaces' parameter services; changes go to /parameter_events") {
  const DdsOptions opt = options_on(51);
  Flight f("dds_rcl", 1.0);
  DdsBridge bridge(*f.host, opt);
  auto* p = ddsi::make_participant(opt, "ros2_tool");
  auto* pub = p->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  auto* sub = p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  using namespace rcl_interfaces::srv;
  // names and types as rmw_fastrtps maps them
  CHECK(fdds::TypeSupport(new GetParameters_RequestPubSubType()).get_type_name() == "rcl_interfaces::srv::dds_::GetParameters_Request_");
  CHECK(ddsi::request_topic("tern/ctl", "get_parameters") == "rq/tern/ctl/get_parametersRequest");
  CHECK(ddsi::reply_topic("tern/ctl", "get_parameters") == "rr/tern/ctl/get_parametersReply");
  fdds::DataReaderQos eq = ddsi::reader_qos(DdsQos::reliable);
  auto* events = sub->create_datareader(ddsi::make_topic<rcl_interfaces::msg::ParameterEventPubSubType>(p, "rt/parameter_events"), eq);
  REQUIRE(events != nullptr);

  ListParameters_Request lq;
  const auto names =
      ros_call<ListParameters_RequestPubSubType, ListParameters_ResponsePubSubType>(p, pub, sub, "ctl", "list_parameters", lq);
  CHECK(names.result().names() == std::vector<std::string>{"aileron", "fail_at", "fail_mode", "h_target", "kp", "tag"});
  DescribeParameters_Request dq;
  dq.names({"kp", "nope"});
  const auto d =
      ros_call<DescribeParameters_RequestPubSubType, DescribeParameters_ResponsePubSubType>(p, pub, sub, "ctl", "describe_parameters", dq);
  REQUIRE(d.descriptors().size() == 2);
  const auto& kp = d.descriptors()[0];
  CHECK(kp.name() == "kp");
  CHECK(kp.type() == ddsi::kDouble);
  CHECK(kp.description() == "throttle per metre of altitude error");
  CHECK(kp.additional_constraints() == "unit: 1/m; default: 0.05");
  CHECK_FALSE(kp.read_only());
  REQUIRE(kp.floating_point_range().size() == 1);
  CHECK(kp.floating_point_range()[0].from_value() == 0.0);
  CHECK(kp.floating_point_range()[0].to_value() == 10.0);
  CHECK(d.descriptors()[1].type() == ddsi::kNotSet);
  dq.names({"h0"});
  const auto h0 = ros_call<DescribeParameters_RequestPubSubType, DescribeParameters_ResponsePubSubType>(p, pub, sub, "sensor",
                                                                                                        "describe_parameters", dq);
  CHECK(h0.descriptors().at(0).read_only());  // start-only

  // set: one good, one out of range; atomically: nothing when one is bad
  SetParameters_Request sq;
  rcl_interfaces::msg::Parameter good, bad;
  good.name("tag");
  good.value(ddsi::to_rcl(0.5));
  bad.name("kp");
  bad.value(ddsi::to_rcl(50.0));
  sq.parameters({good, bad});
  const auto sr = ros_call<SetParameters_RequestPubSubType, SetParameters_ResponsePubSubType>(p, pub, sub, "ctl", "set_parameters", sq);
  REQUIRE(sr.results().size() == 2);
  CHECK(sr.results()[0].successful());
  CHECK_FALSE(sr.results()[1].successful());
  CHECK(sr.results()[1].reason() == "parameter 'ctl.kp': value 50 is outside the valid range [0, 10] 1/m");
  SetParametersAtomically_Request aq;
  good.value(ddsi::to_rcl(0.75));
  aq.parameters({good, bad});
  const auto ar = ros_call<SetParametersAtomically_RequestPubSubType, SetParametersAtomically_ResponsePubSubType>(
      p, pub, sub, "ctl", "set_parameters_atomically", aq);
  CHECK_FALSE(ar.result().successful());
  GetParameters_Request gq;
  gq.names({"tag", "nope"});
  const auto gr = ros_call<GetParameters_RequestPubSubType, GetParameters_ResponsePubSubType>(p, pub, sub, "ctl", "get_parameters", gq);
  REQUIRE(gr.values().size() == 2);
  CHECK(gr.values()[0].type() == ddsi::kDouble);
  CHECK(gr.values()[0].double_value() == 0.0);    // between flights a change waits for the next flight's first tick
  CHECK(gr.values()[1].type() == ddsi::kNotSet);  // as rclcpp answers an unknown name
  // the accepted change, and only it, on /parameter_events
  rcl_interfaces::msg::ParameterEvent e;
  fdds::SampleInfo si;
  REQUIRE(ddsi::wait_until([&] { return events->take_next_sample(&e, &si) == ReturnCode_t::RETCODE_OK && si.valid_data; },
                           std::chrono::seconds(5)));
  CHECK(e.node() == "/tern/ctl");
  REQUIRE(e.changed_parameters().size() == 1);
  CHECK(e.changed_parameters()[0].name() == "tag");
  CHECK(e.changed_parameters()[0].value().double_value() == 0.5);
  CHECK(events->take_next_sample(&e, &si) != ReturnCode_t::RETCODE_OK);

  // `ros2 node list`: the nodes announced on ros_discovery_info
  DdsClient client(opt, std::chrono::seconds(20));
  const auto nodes = client.nodes();
  INFO(fmt::format("{}", fmt::join(nodes, " ")));
  CHECK(nodes == std::vector<std::string>{"sensor", "filter", "ctl", "metrics"});  // schedule order, then the host's own
  const DdsParam described = client.param_get("ctl.kp");
  CHECK(described.unit == "1/m");
  CHECK(std::get<double>(described.default_value) == 0.05);
  CHECK(client.param_get("sensor.h0").read_only);
  ddsi::delete_participant(p);
}

namespace {

/// Bytes written as they are on a topic of any type name: what a hostile or broken participant
/// sends (serialize copies the sample's bytes, encapsulation header included).
class RawBytesType final : public fdds::TopicDataType {
 public:
  explicit RawBytesType(const std::string& type_name) {
    setName(type_name.c_str());
    m_typeSize = 1024;
    m_isGetKeyDefined = false;
  }
  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override {
    const auto& bytes = *static_cast<std::vector<std::uint8_t>*>(data);
    std::copy(bytes.begin(), bytes.end(), payload->data);
    payload->length = static_cast<std::uint32_t>(bytes.size());
    return true;
  }
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t*, void*) override { return false; }
  std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override {
    return [data] { return static_cast<std::uint32_t>(static_cast<std::vector<std::uint8_t>*>(data)->size()); };
  }
  void* createData() override { return new std::vector<std::uint8_t>(); }
  void deleteData(void* data) override { delete static_cast<std::vector<std::uint8_t>*>(data); }
  bool getKey(void*, eprosima::fastrtps::rtps::InstanceHandle_t*, bool) override { return false; }
};

}  // namespace

TEST_CASE("dds: a request whose bytes no client writes (a bad encapsulation, a bool of 2) is dropped; the vehicle serves on (issue 78)") {
  // as between processes: every sample through the UDP transport and Fast DDS's receive threads
  // (within one process Fast DDS hands a sample to the reader in the writer's own call)
  auto settings = eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings();
  const auto intraprocess = settings.intraprocess_delivery;
  settings.intraprocess_delivery = eprosima::fastrtps::INTRAPROCESS_OFF;
  eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(settings);
  struct Restore {
    eprosima::fastrtps::IntraprocessDeliveryType was;
    ~Restore() {
      auto s = eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings();
      s.intraprocess_delivery = was;
      eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(s);
    }
  } restore{intraprocess};
  DdsOptions opt = options_on(52);
  Flight f("dds_undecodable", 4.0, "phases: {takeoff: ctl, climb: ctl, cruise: ctl}\nphase_machine: {preflight: false}\n");
  DdsBridge bridge(*f.host, opt);
  auto* p = ddsi::make_participant(opt, "hostile");
  auto* pub = p->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  rosplane_msgs::srv::AddWaypoint_RequestPubSubType real;
  fdds::TypeSupport raw(new RawBytesType(real.getName()));
  REQUIRE(raw.register_type(p) == ReturnCode_t::RETCODE_OK);
  auto* topic = p->create_topic(ddsi::request_topic("tern", "add_waypoint"), raw.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
  auto* w = pub->create_datawriter(topic, ddsi::service_writer_qos());
  REQUIRE(w != nullptr);
  REQUIRE(ddsi::wait_until([&] { return writer_matched(w); }, std::chrono::seconds(10)));
  f.start();
  // a valid request's bytes (CDR, little endian), then two that Fast CDR refuses
  rosplane_msgs::srv::AddWaypoint_Request rq;
  rq.w({100.0F, -50.0F, -40.0F});
  rq.va_d(18.0F);
  eprosima::fastrtps::rtps::SerializedPayload_t sp(real.getSerializedSizeProvider(&rq)());
  REQUIRE(real.serialize(&rq, &sp));
  std::vector<std::uint8_t> bad_bool(sp.data, sp.data + sp.length), bad_header = bad_bool;
  REQUIRE(bad_bool.size() > 16);
  bad_bool[4 + 12] = 2;  // `lla` (after w[3]): a CDR boolean is 0 or 1
  bad_header[0] = 7;     // the encapsulation's first byte is 0
  REQUIRE(w->write(&bad_header));
  REQUIRE(w->write(&bad_bool));
  DdsClient client(opt, std::chrono::seconds(20));
  tern::msg::Waypoint wp;
  wp.w = Eigen::Vector3d(100.0, -50.0, -40.0);
  wp.Va_d = 18.0;
  client.mission_add(wp);  // answered: the vehicle is alive and serving
  const FlightResult r = f.finish();
  REQUIRE(r.ok);
  const auto s = nlohmann::json::parse(read_file(r.run_dir / "summary.json"));
  CHECK(s["instances"]["filter"]["mission_edits"] == 1.0);
  ddsi::delete_participant(p);
}

namespace {

template <class PubSub>
std::vector<std::uint8_t> serialized(typename PubSub::type sample) {
  PubSub type;
  eprosima::fastrtps::rtps::SerializedPayload_t p(type.getSerializedSizeProvider(&sample)());
  REQUIRE(type.serialize(&sample, &p));
  return {p.data, p.data + p.length};
}

template <class PubSub>
typename PubSub::type deserialized(const std::vector<std::uint8_t>& bytes) {
  eprosima::fastrtps::rtps::SerializedPayload_t p(static_cast<std::uint32_t>(bytes.size()));
  std::copy(bytes.begin(), bytes.end(), p.data);
  p.length = static_cast<std::uint32_t>(bytes.size());
  typename PubSub::type sample;
  REQUIRE(PubSub().deserialize(&p, &sample));
  return sample;
}

}  // namespace

TEST_CASE("dds: answer(): a request's bytes as the wire hands them get the reply's; bytes that do not decode get none") {
  Flight f("dds_answer", 1.0);
  DdsBridge bridge(*f.host, options_on(53));
  const auto services = bridge.services();
  for (const char* s : {"tern/add_waypoint", "tern/status", "tern/param_save", "tern/ctl/set_parameters", "tern/filter/list_parameters"})
    CHECK_MESSAGE(std::count(services.begin(), services.end(), s) == 1, s);
  rosplane_msgs::srv::AddWaypoint_Request rq;
  rq.w({100.0F, -50.0F, -40.0F});
  rq.va_d(18.0F);
  auto bytes = serialized<rosplane_msgs::srv::AddWaypoint_RequestPubSubType>(rq);
  const auto reply = bridge.answer("tern/add_waypoint", bytes);
  REQUIRE(reply.has_value());
  const auto r = deserialized<rosplane_msgs::srv::AddWaypoint_ResponsePubSubType>(*reply);
  CHECK(r.success());
  CHECK(f.host->queued_mission_edits() == 1);
  bytes[4 + 12] = 2;  // `lla`, a CDR boolean, neither 0 nor 1
  CHECK_FALSE(bridge.answer("tern/add_waypoint", bytes).has_value());
  CHECK_FALSE(bridge.answer("tern/add_waypoint", {}).has_value());
  CHECK(f.host->queued_mission_edits() == 1);
  rcl_interfaces::srv::SetParameters_Request set;
  rcl_interfaces::msg::Parameter kp;
  kp.name("kp");
  kp.value().type(3);             // PARAMETER_DOUBLE
  kp.value().double_value(20.0);  // outside [0, 10]
  rcl_interfaces::msg::Parameter h = kp;
  h.name("h_target");
  h.value().double_value(40.0);
  set.parameters({kp, h});  // (the accepted one is published on /parameter_events with the bridge's
                            // options, which outlive the temporary the bridge was built from)
  const auto set_reply = bridge.answer("tern/ctl/set_parameters", serialized<rcl_interfaces::srv::SetParameters_RequestPubSubType>(set));
  REQUIRE(set_reply.has_value());
  const auto sr = deserialized<rcl_interfaces::srv::SetParameters_ResponsePubSubType>(*set_reply);
  REQUIRE(sr.results().size() == 2);
  CHECK_FALSE(sr.results()[0].successful());
  CHECK(sr.results()[0].reason().find("kp") != std::string::npos);
  CHECK(sr.results()[1].successful());
  CHECK_THROWS_WITH_AS(bridge.answer("tern/add_waypoints", bytes),
                       "DDS: no service 'tern/add_waypoints' on this vehicle (did you mean 'tern/add_waypoint'?)", DdsError);
}
