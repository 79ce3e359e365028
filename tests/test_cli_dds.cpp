// The DDS command line against a running `tern fly --dds`: two processes, loopback only, a
// domain of their own (183/184: 83 is used by the same test of other checkouts on this machine).
#include <doctest/doctest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <regex>
#include <thread>
#include <tuple>

#include "test_util.hpp"

namespace {
std::pair<int, std::string> run_tern(const std::string& args) {
  const fs::path out = test_dir() / "cli_dds.out";
  const int rc = std::system((std::string(TERN_BIN) + " " + args + " > " + out.string() + " 2>&1").c_str());
  return {WEXITSTATUS(rc), read_file(out)};
}
}  // namespace

TEST_CASE("tern topics, echo, param and mission against a flying vehicle") {
  const fs::path logs = test_dir() / "cli_dds_runs";
  const std::string mission = std::string(TERN_SOURCE_DIR) + "/configs/missions/default.yaml";
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    execl(TERN_BIN, TERN_BIN, "fly", mission.c_str(), "--dds", "--dds-domain", "183", "--realtime", "--duration", "900", "--log-dir",
          logs.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  struct Reaper {  // a failed REQUIRE must not leave the vehicle flying on the test's domain
    pid_t pid;
    bool done = false;
    int status = 0;
    // false once the vehicle has exited (reaped here): the polls below stop instead of waiting
    // out each command's time-out against nobody (the flight is ended by SIGINT at the end).
    bool alive() {
      if (!done && waitpid(pid, &status, WNOHANG) == pid) done = true;
      return !done;
    }
    ~Reaper() {
      if (done) return;
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
    }
  } reaper{pid};
  const std::string d = " --domain 183 --timeout 20";
  // the vehicle process is starting (plugins, estimator, DDS participant): ask until it answers
  int rc0 = 1;
  std::string topics;
  for (int i = 0; i < 3 && rc0 != 0; ++i) std::tie(rc0, topics) = run_tern("topics" + d);
  REQUIRE_MESSAGE(rc0 == 0, topics);
  CHECK(topics.find("rt/tern/state                            rosplane_msgs::msg::dds_::State_") != std::string::npos);
  auto [rc1, echo] = run_tern("echo state --once" + d);
  CHECK(rc1 == 0);
  CHECK(echo.find("p_n: ") != std::string::npos);
  CHECK(echo.find("header.stamp: ") != std::string::npos);
  auto [rc1f, field] = run_tern("echo state --once --field va" + d);
  CHECK_MESSAGE(rc1f == 0, field);
  CHECK(std::regex_match(field, std::regex("[-0-9.e]+\n---\n")));
  auto [rc1h, hz] = run_tern("hz state --duration 1.5" + d);
  CHECK_MESSAGE(rc1h == 0, hz);
  CHECK(hz.rfind("average rate: ", 0) == 0);
  CHECK(hz.find("window: ") != std::string::npos);
  // issue 20: file names from the network stay inside the vehicle's allowed directories
  auto [rc1s, shadow] = run_tern("mission load ../../../../etc/shadow" + d);
  CHECK(rc1s == 1);
  CHECK(shadow.rfind("tern: error: load_mission_from_file: refused '../../../../etc/shadow': '..' is not allowed", 0) == 0);
  CHECK(run_tern("param save params.yaml" + d).first == 0);
  auto [rc1o, again] = run_tern("param save params.yaml" + d);
  CHECK(rc1o == 1);
  CHECK(again == "tern: error: param_save: refused: " + (logs / "params.yaml").string() + " exists (ask to overwrite it: --overwrite)\n");
  CHECK(run_tern("param save params.yaml --overwrite" + d).first == 0);
  auto [rc2, set] = run_tern("param set slc.roll_kp 0.5" + d);
  CHECK(rc2 == 0);
  CHECK(set == "slc.roll_kp = 0.5 (applied at the vehicle's next tick)\n");
  auto [rc3, refused] = run_tern("param set slc.roll_kp 99" + d);
  CHECK(rc3 == 1);
  CHECK(refused == "tern: error: parameter 'slc.roll_kp': value 99 is outside the valid range [0, 10] rad/rad\n");
  std::string get;
  for (int i = 0; i < 50 && reaper.alive(); ++i) {  // applied at the vehicle's next tick
    get = run_tern("param get slc.roll_kp" + d).second;
    if (get.rfind("slc.roll_kp                        0.5 ", 0) == 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  CHECK_MESSAGE(get.rfind("slc.roll_kp                        0.5 ", 0) == 0, get);
  auto [rc4d, desc] = run_tern("param describe slc.roll_kp" + d);  // through rcl_interfaces describe_parameters
  CHECK_MESSAGE(rc4d == 0, desc);
  CHECK(desc.rfind("slc.roll_kp (double, rad/rad)\n", 0) == 0);
  CHECK(desc.find("\n  range: [0, 10]\n") != std::string::npos);
  CHECK(desc.find("\n  changes in flight at the next tick\n") != std::string::npos);
  // the default mission ends with a land item, after which nothing is added: a new list, ending
  // with a land item through tern's add_mission_item (ROSplane's AddWaypoint has no item type)
  auto [rc5, add] = run_tern("mission add 100 -100 -60 --Va 17 --set-current" + d);
  CHECK_MESSAGE(rc5 == 0, add);
  auto [rc5l, land] = run_tern("mission add 0 0 0 --Va 15 --land 2.3562 --flare-height 3" + d);
  CHECK_MESSAGE(rc5l == 0, land);
  CHECK(land == "land item added\n");
  std::string print;
  for (int i = 0; i < 50 && reaper.alive(); ++i) {  // the planner applies the edits at its next steps
    print = run_tern("mission print" + d).second;
    if (print.find("2 waypoints") != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  CHECK_MESSAGE(print.find("2 waypoints") != std::string::npos, print);
  CHECK(print.find("w [100.000, -100.000, -60.000]") != std::string::npos);
  CHECK_MESSAGE(print.find("chi_d 2.3562 rad land (chi_d: the runway heading): glide slope 0.0873 rad, flare 3 m, decision 12 m") !=
                    std::string::npos,
                print);
  CHECK(run_tern("mission clear" + d).first == 0);
  for (int i = 0; i < 50 && reaper.alive(); ++i) {
    print = run_tern("mission print" + d).second;
    if (print.find("0 waypoints") != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  CHECK_MESSAGE(print.find("0 waypoints") != std::string::npos, print);
  auto [rc6, none] = run_tern("param get slc.roll_kp --domain 184 --timeout 0.5");
  CHECK(rc6 == 1);
  CHECK(none == "tern: error: no vehicle announced its nodes (ros_discovery_info) on DDS domain 184, namespace 'tern' within 0.5 s\n");
  REQUIRE_MESSAGE(reaper.alive(), "the vehicle exited before the test ended it (status " << reaper.status << ")");
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  reaper.done = true;
  CHECK(WEXITSTATUS(status) == 130);
  std::vector<fs::path> runs;
  for (const auto& e : fs::directory_iterator(logs)) runs.push_back(e.path());
  std::erase_if(runs, [](const fs::path& p) { return !fs::is_directory(p); });  // params.yaml
  REQUIRE(runs.size() == 1);
  // the waypoint lists as flown: the added waypoint and land item in a list's items, then the cleared list (no items)
  const std::string items = read_file(runs[0] / "topics" / "waypoints_items.csv");
  CHECK(items.rfind("t [s],stamp [ns],revision [],index [],w_0 [m|deg],w_1 [m|deg],w_2 [m|deg],lla [bool],", 0) == 0);
  CHECK(items.find(",0,100,-100,-60,0,") != std::string::npos);  // the new list's first
  CHECK(items.find(",1,0,0,0,0,2.3562,") != std::string::npos);  // its land item: the touchdown point, the runway heading
  const auto lists = lines(read_file(runs[0] / "topics" / "waypoints.csv"));
  REQUIRE(lists.size() >= 5);  // header, the mission, the two edits, the clear
  CHECK(cells(lists.back())[3] == "0");
  const std::string params = read_file(runs[0] / "params.csv");
  CHECK(params.find(",slc.roll_kp,0.5,dds\n") != std::string::npos);
  CHECK(params.find(",slc.roll_kp,99,") == std::string::npos);
}
