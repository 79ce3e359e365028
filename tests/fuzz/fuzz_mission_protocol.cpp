// fuzz_mission_protocol: libFuzzer target for the ground station's mission protocol
// (core/apps/mavlink/mission_protocol.hpp MissionProtocol: MISSION, FENCE and RALLY uploads,
// downloads, clear, set current, the item and list checks of mission_items.hpp and fence_items.hpp),
// driven by a sequence of decoded MAVLink messages without a socket or the link's thread. Its host
// is built once from the test plugins (tests/plugins: test_sensor, test_filter publishing a state
// with a valid origin and reading `mission_edit`, test_controller; a config geofence polygon and a
// rally point) and flies one 0.2-s flight first, so that the flight view has the estimate's origin
// the protocol places lat/lon with; nothing flies while the inputs are fed.
//
// The input is records [op][flags][payload]: op picks MISSION_COUNT, MISSION_ITEM_INT,
// MISSION_REQUEST_LIST, MISSION_REQUEST_INT, MISSION_REQUEST, MISSION_CLEAR_ALL,
// MISSION_SET_CURRENT, MISSION_ACK (the payload: the message's full wire length, zero-filled where
// the input ends: any mission_type, counts up to 65535, NaN parameters), or a call the link makes
// (fly_from(seq) for MAV_CMD_MISSION_START, keep_mission before a command's list, on_tick,
// current_seq); flags bit 0 addresses the message to the vehicle (target 1/1) over whatever the
// payload says, bit 1 picks the sender (GCS 255 or 254). A fresh MissionProtocol takes each input.
//
// Promised, whatever comes: no crash, no exception out of a handler, bounded memory; every reply
// well-formed: MISSION_ACK, MISSION_REQUEST_INT, MISSION_COUNT or MISSION_ITEM_INT only, of the
// message's full length, to a sender of this input, a result among MAV_MISSION_RESULT, a
// mission_type among MISSION, FENCE, RALLY (ALL for a clear) unless the answer is UNSUPPORTED, an
// upload's request for an item below kMaxItems, every STATUSTEXT one non-empty line of a valid
// severity. After the input, a download of each list as a GCS makes it (REQUEST_LIST, then
// REQUEST_INT 0..count-1) gives exactly count items numbered 0..count-1, the items the protocol
// lists; and the protocol's directory is gone once it is. The mission edits an input queued on the
// host (at most RemoteQueue::kMaxQueued: more are refused) are then flown off in a flight of as
// many ticks, so that every input meets the same host.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "flight/host.hpp"
#include "fuzz_host.hpp"
#include "mavlink/flight_view.hpp"
#include "mavlink/mission_protocol.hpp"

using namespace tern::core;
using namespace tern::core::mavlink;
namespace fs = std::filesystem;

namespace {

constexpr std::uint8_t kSystemId = 1;

struct World {
  std::unique_ptr<Host> host;
  std::unique_ptr<FlightWatch> watch;
  FailsafeStation::Geometry config;  // the config's zones and rally point
  fs::path dir, runs;
};

World& world() {
  static World w = [] {
    auto built = tern::fuzz::test_plugin_host("mission_protocol_fuzz",
                                              "failsafes:\n"
                                              "  geofence: {max_distance: 2000, min_altitude: 0, max_altitude: 300,\n"
                                              "             polygon: [[600, -400], [600, 400], [-600, 400], [-600, -400]]}\n"
                                              "  rally: [[300, 200, 80]]\n");
    World made;
    made.host = std::move(built.host);
    made.runs = built.runs;
    made.watch = std::make_unique<FlightWatch>(*made.host);
    made.host->fly();  // the flight view gets the estimate's origin
    if (!made.watch->view().has_state) __builtin_trap();
    made.config = made.host->fence_geometry();
    made.dir = built.dir / "mission";
    return made;
  }();
  return w;
}

/// The replies of one input, checked as they are sent.
struct Replies {
  std::set<std::uint8_t> senders;  // the systems this input's messages came from
  std::vector<MissionItemInt> items;
  std::vector<MissionCount> counts;
  std::vector<MissionAck> acks;

  void send(std::uint32_t msgid, const std::vector<std::uint8_t>& payload) {
    const auto info = message_info(msgid);
    if (!info || payload.size() != info->length) __builtin_trap();
    Frame f;
    f.msgid = msgid;
    f.payload = payload;
    std::uint8_t target = 0, type = 0;
    if (msgid == MissionAck::kId) {
      const auto a = decode<MissionAck>(f);
      if (a.type > MAV_MISSION_OPERATION_CANCELLED) __builtin_trap();
      const bool known = a.mission_type <= MAV_MISSION_TYPE_RALLY || a.mission_type == MAV_MISSION_TYPE_ALL;
      if (!known && a.type != MAV_MISSION_UNSUPPORTED) __builtin_trap();
      target = a.target_system;
      acks.push_back(a);
      if (verbose()) std::fprintf(stderr, "MISSION_ACK %u of mission type %u\n", a.type, a.mission_type);
      return check_target(target);
    }
    if (msgid == MissionRequestInt::kId) {
      const auto r = decode<MissionRequestInt>(f);
      if (r.seq >= MissionProtocol::kMaxItems) __builtin_trap();
      target = r.target_system, type = r.mission_type;
    } else if (msgid == MissionCount::kId) {
      const auto c = decode<MissionCount>(f);
      target = c.target_system, type = c.mission_type;
      counts.push_back(c);
    } else if (msgid == MissionItemInt::kId) {
      const auto it = decode<MissionItemInt>(f);
      target = it.target_system, type = it.mission_type;
      items.push_back(it);
    } else {
      __builtin_trap();  // the protocol answers with these four only
    }
    if (type > MAV_MISSION_TYPE_RALLY) __builtin_trap();
    check_target(target);
  }
  void check_target(std::uint8_t target) const {
    if (!senders.count(target)) __builtin_trap();
  }
  static void say(std::uint8_t severity, const std::string& text) {
    if (severity > 7 /* MAV_SEVERITY_DEBUG */ || text.empty() || text.find('\n') != std::string::npos) __builtin_trap();
    if (verbose()) std::fprintf(stderr, "STATUSTEXT %u: %s\n", severity, text.c_str());
  }
  /// TERN_FUZZ_VERBOSE: the protocol's answers on stderr (what a seed runs into)
  static bool verbose() {
    static const bool v = std::getenv("TERN_FUZZ_VERBOSE") != nullptr;
    return v;
  }
};

/// A message of type T from the input's payload bytes (zero-filled past the input's end).
template <class T>
Frame frame(const std::uint8_t*& p, const std::uint8_t* end, std::uint8_t flags, Replies& r) {
  Frame f;
  f.msgid = T::kId;
  f.sysid = (flags & 2) ? 254 : 255;
  f.compid = 190;
  const std::size_t n = std::min<std::size_t>(T::kLength, static_cast<std::size_t>(end - p));
  f.payload.assign(p, p + n);
  f.payload.resize(T::kLength, 0);
  p += n;
  if (flags & 1) {
    T m = decode<T>(f);
    if constexpr (requires { m.target_system; }) {
      m.target_system = kSystemId;
      m.target_component = MAV_COMP_ID_AUTOPILOT1;
    }
    f.payload = encode(m);
  }
  r.senders.insert(f.sysid);
  return f;
}

/// A download of list `type` as a GCS makes it: count, then every item, numbered 0..count-1.
void download(MissionProtocol& proto, Replies& r, std::uint8_t type) {
  const std::vector<MissionItemInt> listed = proto.items(type);
  MissionRequestList rl;
  rl.target_system = kSystemId;
  rl.target_component = MAV_COMP_ID_AUTOPILOT1;
  rl.mission_type = type;
  Frame f;
  f.msgid = MissionRequestList::kId;
  f.sysid = 255;
  f.compid = 190;
  f.payload = encode(rl);
  r.counts.clear();
  proto.on_frame(f);
  if (r.counts.size() != 1 || r.counts[0].count != listed.size() || r.counts[0].mission_type != type) __builtin_trap();
  for (std::uint16_t i = 0; i < r.counts[0].count; ++i) {
    MissionRequestInt rq;
    rq.seq = i;
    rq.target_system = kSystemId;
    rq.target_component = MAV_COMP_ID_AUTOPILOT1;
    rq.mission_type = type;
    f.msgid = MissionRequestInt::kId;
    f.payload = encode(rq);
    r.items.clear();
    proto.on_frame(f);
    if (r.items.size() != 1 || r.items[0].seq != i || r.items[0].mission_type != type) __builtin_trap();
    MissionItemInt expected = listed[i];
    expected.target_system = 255, expected.target_component = 190, expected.mission_type = type;
    if (encode(r.items[0]) != encode(expected)) __builtin_trap();  // the item listed, as it is listed
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  World& w = world();
  Replies r;
  r.senders.insert(255);                    // the download below
  w.host->set_fence_zones(w.config.zones);  // each input from the same host state: the config's
  w.host->set_rally_points(w.config.rally);
  {
    MissionProtocol proto(*w.host, *w.watch,
                          Outbox{[&r](std::uint32_t id, const std::vector<std::uint8_t>& p) { r.send(id, p); }, &Replies::say}, kSystemId,
                          w.dir);
    const std::uint8_t* p = data;
    const std::uint8_t* end = data + size;
    while (end - p >= 2) {
      const std::uint8_t op = p[0] % 9, flags = p[1];
      p += 2;
      switch (op) {
        case 0: proto.on_frame(frame<MissionCount>(p, end, flags, r)); break;
        case 1: proto.on_frame(frame<MissionItemInt>(p, end, flags, r)); break;
        case 2: proto.on_frame(frame<MissionRequestList>(p, end, flags, r)); break;
        case 3: proto.on_frame(frame<MissionRequestInt>(p, end, flags, r)); break;
        case 4: proto.on_frame(frame<MissionRequest>(p, end, flags, r)); break;
        case 5: proto.on_frame(frame<MissionClearAll>(p, end, flags, r)); break;
        case 6: proto.on_frame(frame<MissionSetCurrent>(p, end, flags, r)); break;
        case 7: proto.on_frame(frame<MissionAck>(p, end, flags, r)); break;
        default: {  // the link's own calls
          std::uint16_t seq = 0;
          const std::size_t n = std::min<std::size_t>(2, static_cast<std::size_t>(end - p));
          std::memcpy(&seq, p, n);
          p += n;
          switch (flags % 4) {
            case 0: {
              const std::string why = proto.fly_from(seq);
              if (why.find('\n') != std::string::npos) __builtin_trap();
              break;
            }
            case 1: proto.keep_mission(); break;
            case 2: proto.on_tick(); break;
            default: (void)proto.current_seq(); break;
          }
        }
      }
    }
    for (std::uint8_t type : {MAV_MISSION_TYPE_MISSION, MAV_MISSION_TYPE_FENCE, MAV_MISSION_TYPE_RALLY}) download(proto, r, type);
  }
  if (fs::exists(w.dir)) __builtin_trap();  // the uploads' files went with the protocol
  // the mission edits the input queued on the host (accepted uploads, clears, set current) flown
  // off, one per tick, so that every input starts from the same host (at most kMaxQueued wait:
  // more are refused)
  if (const std::size_t n = w.host->queued_mission_edits(); n > 0) {
    if (n > RemoteQueue::kMaxQueued) __builtin_trap();
    w.host->set_duration(static_cast<double>(n + 1) * tern::to_seconds(w.host->base_period()));
    w.host->fly();
    std::error_code ec;
    fs::remove_all(w.runs, ec);
  }
  return 0;
}
