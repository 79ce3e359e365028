// core/apps/mavlink/gcs_vehicle.cpp: one vehicle behind the ground-station endpoint (gcs_vehicle.hpp).
#include "mavlink/gcs_vehicle.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <set>

#include "flight/host.hpp"
#include "mavlink/component_metadata.hpp"
#include "mavlink/gcs_commands.hpp"
#include "mavlink/mavlink_ftp.hpp"
#include "mavlink/mavlink_messages.hpp"
#include "mavlink/mission_protocol.hpp"
#include "mavlink/param_ids.hpp"
#include "mavlink/telemetry.hpp"
#include "tern/geodesy.hpp"
#include "tern/msg/all.hpp"

namespace tern::core::mavlink {
namespace {

using Clock = std::chrono::steady_clock;

constexpr Nanos kSnapshotPeriod = 20'000'000;  // flight time between copies, ns (50 Hz)
constexpr std::size_t kMaxEvents = 32;         // STATUSTEXTs waiting to be sent
constexpr std::size_t kParamsPerTick = 25;     // PARAM_VALUEs of a list sent per 10-ms tick

struct Event {
  std::uint8_t severity;
  std::string text;
};

}  // namespace

struct GcsVehicle::Impl {
  Impl(Host& h, std::uint8_t id, FrameSink s, const std::filesystem::path& dir)
      : host(h), system_id(id), sink(std::move(s)), table(numeric_params(h)), ftp(metadata_files(table, h)) {
    for (const auto& t : host.topics()) topics.insert(t.name);
    const Outbox out{[this](std::uint32_t msgid, const std::vector<std::uint8_t>& payload) { send_frame(msgid, payload); },
                     [this](std::uint8_t severity, const std::string& text) { say(severity, text); }};
    watch = std::make_unique<FlightWatch>(host);
    mission = std::make_unique<MissionProtocol>(host, *watch, out, system_id, dir);
    commands = std::make_unique<GcsCommands>(host, *watch, *mission, out, system_id);
  }

  /// What MAVLink FTP serves: the component metadata (component_metadata.hpp).
  static std::map<std::string, std::string> metadata_files(const ParamTable& t, const Host& h) {
    MetadataFiles m = component_metadata(t, h.parameters());
    return {{kGeneralMetadataFile, std::move(m.general)}, {kParameterMetadataFile, std::move(m.parameters)}};
  }

  static std::vector<std::pair<std::string, ParamKind>> numeric_params(const Host& h) {
    std::vector<std::pair<std::string, ParamKind>> out;
    for (const auto& [name, p] : h.parameters()) out.emplace_back(name, p->kind());
    return out;
  }

  // ---- flight thread ----
  void observe(Nanos now) {
    if (now == 0) {  // a new flight
      last_phase.reset();
      handovers_seen = 0;
      failsafes_seen = 0;
    }
    const auto& handovers = host.handovers();
    if (handovers.size() < handovers_seen) handovers_seen = 0;
    while (handovers_seen < handovers.size()) {
      const auto& h = handovers[handovers_seen++];
      push_event(MAV_SEVERITY_WARNING, "controller " + h.to + ": " + h.reason);
    }
    const auto& failsafes = host.failsafe_events();
    if (failsafes.size() < failsafes_seen) failsafes_seen = 0;
    while (failsafes_seen < failsafes.size()) {  // each engagement and its end, as the log says it
      const FailsafeEvent& e = failsafes[failsafes_seen++];
      push_event(e.action == "none" ? MAV_SEVERITY_INFO : MAV_SEVERITY_WARNING, "failsafe " + e.cause + ": " + e.detail);
    }
    if (!topics_tap.take(host, now)) return;
    Snapshot& s = staging;
    s.any = true;
    static_cast<FlightTopics&>(s) = topics_tap.topics();
    const FailsafeStation::FenceStatus fence = host.fence_status();
    s.fence_enabled = fence.enabled;
    s.fence_breached = fence.breached;
    if (s.has_phase && (!last_phase || *last_phase != s.phase.phase)) {
      last_phase = s.phase.phase;
      push_event(MAV_SEVERITY_INFO, "phase " + std::string(msg::phase_name(s.phase.phase)));
    }
    std::lock_guard lk(mu);
    latest = s;
  }

  /// The mission's size and the waypoint flown to, from the mission side's copy of `waypoints`
  /// and `current_path` (flight_view.hpp: one copy of the list, made when the planner republishes it).
  static void mission_of(const FlightView& v, Snapshot& s) {
    s.mission_items.reset();
    s.target.reset();
    if (!v.list) return;
    s.mission_items = v.list->count;
    if (v.waypoint_index >= 0 && static_cast<std::uint32_t>(v.waypoint_index) < v.list->count)
      s.target = v.list->items[static_cast<std::size_t>(v.waypoint_index)];
  }

  void push_event(std::uint8_t severity, std::string text) {
    std::lock_guard lk(mu);
    if (events.size() < kMaxEvents) events.push_back({severity, std::move(text)});
  }

  // ---- the link's thread ----
  void on_frame(const Frame& f) {
    switch (f.msgid) {
      case ParamRequestList::kId: {
        const auto m = decode<ParamRequestList>(f);
        if (for_us(m.target_system, m.target_component)) list_cursor = 0;
        break;
      }
      case ParamRequestRead::kId: on_param_read(decode<ParamRequestRead>(f)); break;
      case ParamSet::kId: on_param_set(decode<ParamSet>(f)); break;
      case Timesync::kId: on_timesync(decode<Timesync>(f), f); break;
      case FileTransferProtocol::kId: on_ftp(decode<FileTransferProtocol>(f), f); break;
      case Heartbeat::kId:  // a ground station's heartbeat feeds the link-loss failsafe, as the DDS bridge's does
        if (decode<Heartbeat>(f).type == MAV_TYPE_GCS) host.ground_link_heard();
        break;
      default:  // missions, commands; else our own messages echoed, a GCS's other traffic
        if (!mission->on_frame(f)) commands->on_frame(f);
        break;
    }
  }

  void on_param_read(const ParamRequestRead& m) {
    if (!for_us(m.target_system, m.target_component)) return;
    std::optional<std::size_t> i;
    if (m.param_index >= 0 && static_cast<std::size_t>(m.param_index) < table.params().size())
      i = static_cast<std::size_t>(m.param_index);
    else if (m.param_index < 0)
      i = table.find(to_string(m.param_id));
    if (i)
      send_param(*i);
    else
      say(MAV_SEVERITY_WARNING, "no parameter " + (m.param_index >= 0 ? std::to_string(m.param_index) : to_string(m.param_id)));
  }

  /// A request (tc1 0) is answered with the link's wall-clock time since it started (ns, never 0:
  /// flight time may run at any speed, and a GCS estimates a clock offset), addressed back.
  void on_timesync(const Timesync& m, const Frame& f) {
    if (m.tc1 != 0 || !for_us(m.target_system, m.target_component)) return;
    const auto since = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - started).count();
    send(Timesync{std::max<std::int64_t>(1, since), m.ts1, f.sysid, f.compid});
  }

  /// MAVLink FTP (mavlink_ftp.hpp): each answer addressed back to the asking system and component.
  void on_ftp(const FileTransferProtocol& m, const Frame& f) {
    if (!for_us(m.target_system, m.target_component)) return;
    for (const FtpPayload& p : ftp.answer(m.payload)) {
      FileTransferProtocol a;
      a.target_system = f.sysid;
      a.target_component = f.compid;
      a.payload = p;
      send(a);
    }
  }

  bool for_us(std::uint8_t sys, std::uint8_t comp) const {
    return (sys == 0 || sys == system_id) && (comp == 0 || comp == MAV_COMP_ID_AUTOPILOT1);
  }

  void on_param_set(const ParamSet& m) {
    if (!for_us(m.target_system, m.target_component)) return;
    const auto i = table.find(to_string(m.param_id));
    if (!i) {
      say(MAV_SEVERITY_WARNING, "no parameter " + to_string(m.param_id));
      return;
    }
    const MavParam& mp = table.params()[*i];
    const ParamBase* p = param(mp.qualified);
    std::optional<tern::ParamValue> accepted;
    std::string why;
    if (p == nullptr) {
      why = mp.qualified + ": no longer in the mission (an instance was swapped)";
    } else if (!std::isfinite(m.param_value)) {
      why = mp.qualified + ": not a finite value";
    } else {
      try {
        const tern::ParamValue v = p->validate(from_mav_value(m.param_value, mp.kind));  // throws ParamError
        host.request_param(mp.qualified, v, "mavlink");                                  // throws: start-only in flight
        accepted = v;
      } catch (const std::exception& e) {
        why = e.what();
      }
    }
    if (accepted) {
      pending[mp.qualified] = {*accepted, Clock::now()};
      send_param(*i);
    } else {
      say(MAV_SEVERITY_WARNING, why);
      if (p != nullptr) send_param(*i);  // refused: the value it keeps, as PX4 answers
    }
  }

  /// The host's parameter `qualified` now (a served host's swap replaces instances), or nullptr.
  const ParamBase* param(const std::string& qualified) const {
    for (const auto& [name, p] : host.parameters())
      if (name == qualified) return p;
    return nullptr;
  }

  /// The value a GCS is told: a change accepted but not yet applied (Host::request_param applies
  /// it at the start of the next tick, a served host's between flights at the next flight's) is
  /// reported as set, as PX4 echoes a PARAM_SET; it is forgotten once the parameter holds it, or a
  /// second after it was asked in flight (another client may have changed the parameter since).
  tern::ParamValue current(const std::string& qualified, const ParamBase& p) {
    const auto it = pending.find(qualified);
    if (it == pending.end()) return host.param_value(p);
    tern::ParamValue now = host.param_value(p);
    if (now == it->second.first || (host.flying() && Clock::now() - it->second.second > std::chrono::seconds(1))) {
      pending.erase(it);
      return now;
    }
    return it->second.first;
  }

  void send_param(std::size_t i) {
    const MavParam& mp = table.params()[i];
    const ParamBase* p = param(mp.qualified);
    if (p == nullptr) return;
    ParamValue v;
    v.param_id = to_chars<16>(mp.id);
    v.param_value = to_mav_value(current(mp.qualified, *p));
    v.param_type = mp.mav_type;
    v.param_count = static_cast<std::uint16_t>(table.params().size());
    v.param_index = static_cast<std::uint16_t>(i);
    send(v);
  }

  /// A text to the GCS, in chunks when it is longer than 50 characters.
  void say(std::uint8_t severity, const std::string& text) {
    if (text.size() > 50 && ++text_id == 0) ++text_id;  // ids of chunked texts: 1, 2, ... (0: one chunk)
    for (const auto& chunk : statustext_chunks(severity, text, text_id)) send(chunk);
  }

  /// A generated message struct (mavlink/common_messages.hpp) in a frame.
  template <class M>
  void send(const M& m) {
    send_frame(M::kId, encode(m));
  }

  static std::uint64_t unix_us() {
    using namespace std::chrono;
    return static_cast<std::uint64_t>(duration_cast<microseconds>(system_clock::now().time_since_epoch()).count());
  }

  void send_frame(std::uint32_t msgid, const std::vector<std::uint8_t>& payload) {
    sink(encode_frame(msgid, payload, seq++, system_id, MAV_COMP_ID_AUTOPILOT1));
  }

  /// Every `period` of wall time, from the link's start.
  bool due(Clock::time_point& next, std::chrono::milliseconds period, Clock::time_point now) {
    if (now < next) return false;
    next = std::max(next + period, now);
    return true;
  }

  void on_tick(const Counters& link) {
    const auto now = Clock::now();
    Snapshot s;
    std::deque<Event> ev;
    {
      std::lock_guard lk(mu);
      s = latest;
      ev.swap(events);
    }
    mission_of(watch->view(), s);
    for (const auto& e : ev) say(e.severity, e.text);
    if (due(next_heartbeat, std::chrono::milliseconds(1000), now)) {
      send(heartbeat(s, host.flying()));
      send(sys_status(s, topics, link));
      send(SystemTime{unix_us(), static_cast<std::uint32_t>(s.t / 1'000'000)});
      if (const auto m = extended_sys_state(s)) send(*m);
      if (auto m = mission_current(s)) {  // seq and total as the GCS's mission items (mission_protocol.hpp)
        if (const auto seq = mission->current_seq()) m->seq = *seq;
        m->total = static_cast<std::uint16_t>(std::min<std::size_t>(mission->items().size(), UINT16_MAX - 1));
        send(*m);
      }
      if (const auto m = wind_cov(s)) send(*m);
    }
    const bool state = s.has_state && s.state.valid && s.state.origin_valid;
    if (state && due(next_attitude, std::chrono::milliseconds(50), now)) send(attitude(s));
    if (state && due(next_position, std::chrono::milliseconds(200), now)) {
      send(global_position(s, origin));
      if (const auto m = nav_controller(s, origin)) send(*m);
    }
    if (s.has_state && due(next_hud, std::chrono::milliseconds(250), now)) send(vfr_hud(s));
    if (s.has_gnss && due(next_gps, std::chrono::milliseconds(500), now)) send(gps_raw(s));
    if (s.has_state && s.state.origin_valid && due(next_home, std::chrono::milliseconds(2000), now)) send(home(s));
    for (std::size_t k = 0; k < kParamsPerTick && list_cursor && *list_cursor < table.params().size(); ++k) send_param((*list_cursor)++);
    if (list_cursor && *list_cursor >= table.params().size()) list_cursor.reset();
    mission->on_tick();
  }

  Host& host;
  std::uint8_t system_id;
  FrameSink sink;
  ParamTable table;
  FtpServer ftp;  // the link's thread
  std::set<std::string> topics;
  Clock::time_point started = Clock::now();
  std::unique_ptr<FlightWatch> watch;
  std::unique_ptr<MissionProtocol> mission;
  std::unique_ptr<GcsCommands> commands;

  // flight thread only
  TopicTap topics_tap{kSnapshotPeriod};
  Snapshot staging;
  std::optional<msg::Phase> last_phase;
  std::size_t handovers_seen = 0;
  std::size_t failsafes_seen = 0;  // failsafe events already said

  // under mu
  std::mutex mu;
  Snapshot latest;
  std::deque<Event> events;

  // the link's thread only
  std::optional<std::size_t> list_cursor;
  std::map<std::string, std::pair<tern::ParamValue, Clock::time_point>> pending;  // accepted sets not yet applied
  std::uint8_t seq = 0;
  std::uint16_t text_id = 0;
  std::optional<GeoOrigin> origin;
  Clock::time_point next_heartbeat{}, next_attitude{}, next_position{}, next_hud{}, next_gps{}, next_home{};
};

GcsVehicle::GcsVehicle(Host& host, std::uint8_t system_id, FrameSink sink, const std::filesystem::path& dir)
    : impl_(std::make_unique<Impl>(host, system_id, std::move(sink), dir)) {}

GcsVehicle::~GcsVehicle() = default;

void GcsVehicle::observe(Nanos now) { impl_->observe(now); }
void GcsVehicle::on_frame(const Frame& f) { impl_->on_frame(f); }
void GcsVehicle::on_tick(const Counters& link) { impl_->on_tick(link); }
Host& GcsVehicle::host() const { return impl_->host; }
std::uint8_t GcsVehicle::system_id() const { return impl_->system_id; }
std::size_t GcsVehicle::param_count() const { return impl_->table.params().size(); }
std::vector<std::pair<std::string, std::string>> GcsVehicle::shortened_ids() const { return impl_->table.shortened(); }

}  // namespace tern::core::mavlink
