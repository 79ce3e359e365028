// DDS Security (issue 20, item 4): a keystore made by `tern dds keystore`, a vehicle flying the
// host's test plugins with dds.security on, on loopback-only participants of this process, DDS
// domain 161 (no other test uses it). A client with the keystore reads State and calls `status`;
// participants without it neither receive State nor get an answer.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <sys/wait.h>

#include <thread>

#include <yaml-cpp/yaml.h>

#include "dds_bridge.hpp"
#include "dds_internal.hpp"
#include "rosplane_msgs/msg/StatePubSubTypes.h"
#include "test_util.hpp"

using namespace tern::core;
namespace fdds = eprosima::fastdds::dds;

namespace {

constexpr std::uint32_t kDomain = 161;

DdsOptions options_on(const std::optional<DdsSecurity>& security) {
  DdsOptions o = parse_dds_options(YAML::Node(), "none.yaml");
  o.enabled = true;
  o.domain = kDomain;
  o.security = security;
  REQUIRE(o.loopback_only());
  return o;
}

/// `tern ARGS` (stdout and stderr): exit status and output.
std::pair<int, std::string> run_tern(const std::string& args) {
  const fs::path out = test_dir() / "tern.out";
  const int rc = std::system((std::string(TERN_BIN) + " " + args + " > " + out.string() + " 2>&1").c_str());
  std::ifstream in(out);
  return {WEXITSTATUS(rc), std::string(std::istreambuf_iterator<char>(in), {})};
}

fs::path make_keystore() {
  const fs::path ks = test_dir() / "keystore";
  for (const std::string& args : {"create " + ks.string(), "add-node " + ks.string() + " vehicle", "add-node " + ks.string() + " ground"}) {
    const auto [rc, out] = run_tern("dds keystore " + args);
    REQUIRE_MESSAGE(rc == 0, out);
  }
  return ks;
}

/// True when a reader of rt/tern/state on a participant without security matches a writer or
/// receives a sample within `wait`.
bool plain_reader_gets_state(std::chrono::seconds wait) {
  auto* p = ddsi::make_participant(options_on(std::nullopt), "outsider");
  auto* sub = p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  auto* reader = sub->create_datareader(ddsi::make_topic<rosplane_msgs::msg::StatePubSubType>(p, "rt/tern/state"),
                                        ddsi::reader_qos(DdsQos::best_effort));
  REQUIRE(reader != nullptr);
  const bool got = reader->wait_for_unread_message(eprosima::fastrtps::Duration_t(static_cast<std::int32_t>(wait.count()), 0));
  fdds::SubscriptionMatchedStatus s;
  reader->get_subscription_matched_status(s);
  ddsi::delete_participant(p);
  return got || s.total_count > 0;
}

}  // namespace

TEST_CASE("dds.security: the config key, relative to the config file; enclave 'vehicle' by default") {
  const DdsOptions o = parse_dds_options(YAML::Load("{security: {keystore: keys}}"), "/m/mission.yaml");
  REQUIRE(o.security);
  CHECK(o.security->keystore == "/m/keys");
  CHECK(o.security->enclave == "vehicle");
  CHECK_THROWS_WITH_AS(parse_dds_options(YAML::Load("{security: {keystore: k, enclave: 'a b'}}"), "m.yaml"),
                       "m.yaml:1:35: dds.security.enclave: 'a b' is not an enclave name (letters, digits, '_', '/')", ConfigError);
  CHECK_THROWS_AS(parse_dds_options(YAML::Load("{security: {enclave: x}}"), "m.yaml"), ConfigError);
}

TEST_CASE("dds security: with the keystore State and status; without it nothing") {
  const fs::path ks = make_keystore();
  for (const char* f : {"public/ca.cert.pem", "private/ca.key.pem", "enclaves/governance.p7s", "enclaves/vehicle/cert.pem",
                        "enclaves/vehicle/key.pem", "enclaves/vehicle/permissions.p7s", "enclaves/ground/identity_ca.cert.pem",
                        "enclaves/ground/permissions_ca.cert.pem", "enclaves/ground/governance.p7s"})
    CHECK_MESSAGE(fs::exists(ks / f), f);

  HostOptions ho;
  ho.quiet = true;
  ho.realtime = true;
  ho.log_dir = test_dir() / "runs";
  std::string cfg = base_config();
  cfg.replace(cfg.find("duration: 2"), 11, "duration: 14");
  Host host(load_config(write_file("secure.yaml", cfg)), ho);
  host.build();
  DdsBridge bridge(host, options_on(DdsSecurity{ks, "vehicle"}));
  std::thread flight([&] { host.fly(); });
  struct Join {
    std::thread& t;
    ~Join() { t.join(); }
  } join{flight};
  REQUIRE(ddsi::wait_until([&] { return host.flying(); }, std::chrono::seconds(5)));

  const auto t0 = std::chrono::steady_clock::now();
  DdsClient ground(options_on(DdsSecurity{ks, "ground"}), std::chrono::seconds(8));
  const DdsStatus st = ground.status();
  CHECK(st.flying);
  std::string state;
  ground.echo("state", [&](const std::string& s) {
    state = s;
    return false;
  });
  CHECK(state.find("va: 15") != std::string::npos);
  MESSAGE("with the keystore: status and a State sample in ", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
          " s; state: ", state.substr(0, state.find('\n')));

  DdsClient outsider(options_on(std::nullopt), std::chrono::seconds(3));
  CHECK_THROWS_WITH_AS(outsider.status(), "no vehicle answered 'status' on DDS domain 161, namespace 'tern' within 3.0 s", DdsError);
  CHECK_FALSE(plain_reader_gets_state(std::chrono::seconds(3)));
  CHECK(host.flying());  // the refusals above happened while the secure vehicle was publishing
}

TEST_CASE("dds security: a missing or bad file is one error line naming it") {
  const fs::path ks = test_dir() / "keystore";  // made by the test case above
  REQUIRE(fs::exists(ks / "enclaves/ground/cert.pem"));
  CHECK_THROWS_WITH_AS(ddsi::make_participant(options_on(DdsSecurity{ks, "nobody"}), "x"),
                       ("dds.security: missing " + (ks / "enclaves/nobody/identity_ca.cert.pem").string() +
                        " (make enclave 'nobody' with `tern dds keystore add-node " + ks.string() + " nobody`)")
                           .c_str(),
                       DdsError);
  fs::copy(ks / "enclaves/ground", ks / "enclaves/broken");
  std::ofstream(ks / "enclaves/broken/key.pem") << "not a key\n";
  CHECK_THROWS_WITH_AS(ddsi::make_participant(options_on(DdsSecurity{ks, "broken"}), "x"),
                       ("dds.security: " + (ks / "enclaves/broken/key.pem").string() + ": not an unencrypted PEM private key").c_str(),
                       DdsError);
  fs::copy_file(ks / "enclaves/vehicle/key.pem", ks / "enclaves/broken/key.pem", fs::copy_options::overwrite_existing);
  CHECK_THROWS_WITH_AS(
      ddsi::make_participant(options_on(DdsSecurity{ks, "broken"}), "x"),
      ("dds.security: " + (ks / "enclaves/broken/key.pem").string() + ": not the key of " + (ks / "enclaves/broken/cert.pem").string())
          .c_str(),
      DdsError);
  fs::copy_file(ks / "enclaves/ground/key.pem", ks / "enclaves/broken/key.pem", fs::copy_options::overwrite_existing);
  {  // permissions edited after signing: everything allowed
    const fs::path p7s = ks / "enclaves/broken/permissions.p7s";
    std::ifstream in(p7s);
    std::string text(std::istreambuf_iterator<char>(in), {});
    const auto at = text.find("<default>DENY</default>");
    REQUIRE(at != std::string::npos);
    text.replace(at, 23, "<default>ALLOW</default>");
    std::ofstream(p7s) << text;
  }
  CHECK_THROWS_WITH_AS(ddsi::make_participant(options_on(DdsSecurity{ks, "broken"}), "x"),
                       ("dds.security: " + (ks / "enclaves/broken/permissions.p7s").string() + ": its signature does not verify with " +
                        (ks / "enclaves/broken/permissions_ca.cert.pem").string())
                           .c_str(),
                       DdsError);
  const auto [rc, out] = run_tern("dds keystore add-node " + ks.string() + " ground");
  CHECK(rc == 1);
  CHECK(out == "tern: error: enclave 'ground' exists already: " + (ks / "enclaves/ground/cert.pem").string() + "\n");
}
