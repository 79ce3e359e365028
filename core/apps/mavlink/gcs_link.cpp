// core/apps/mavlink/gcs_link.cpp: the MAVLink ground-station endpoint (gcs_link.hpp).
#include "mavlink/gcs_link.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <vector>

#include <unistd.h>

#include <boost/asio.hpp>

#include "config/error.hpp"
#include "flight/host.hpp"
#include "mavlink/gcs_commands.hpp"
#include "mavlink/mavlink_messages.hpp"
#include "mavlink/mission_protocol.hpp"
#include "mavlink/param_ids.hpp"
#include "tern/geodesy.hpp"
#include "tern/msg/all.hpp"

namespace tern::core::mavlink {
namespace {

namespace asio = boost::asio;
using udp = asio::ip::udp;
using Clock = std::chrono::steady_clock;

constexpr double kPi = 3.14159265358979323846;
constexpr Nanos kSnapshotPeriod = 20'000'000;  // flight time between copies, ns (50 Hz)
constexpr std::size_t kMaxPeers = 8;
constexpr auto kPeerTimeout = std::chrono::seconds(10);
constexpr std::size_t kMaxEvents = 32;      // STATUSTEXTs waiting to be sent
constexpr std::size_t kParamsPerTick = 25;  // PARAM_VALUEs of a list sent per 10-ms tick
constexpr auto kTick = std::chrono::milliseconds(10);

udp::endpoint parse(const std::string& text, const std::string& what) {
  const std::string where = what.empty() ? std::string() : what + ": ";
  const auto colon = text.rfind(':');
  if (colon == std::string::npos) throw ConfigError(where + "'" + text + "' is not ADDR:PORT (e.g. 127.0.0.1:14550)");
  boost::system::error_code ec;
  const auto addr = asio::ip::make_address_v4(text.substr(0, colon), ec);
  if (ec) throw ConfigError(where + "'" + text.substr(0, colon) + "' is not an IPv4 address");
  const std::string port = text.substr(colon + 1);
  unsigned long p = 0;
  std::size_t used = 0;
  try {
    p = std::stoul(port, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (port.empty() || used != port.size() || p > 65535) throw ConfigError(where + "'" + port + "' is not a port (0-65535)");
  return {addr, static_cast<unsigned short>(p)};
}

/// The latest of what the GCS is shown, copied on the flight thread.
struct Snapshot {
  bool any = false;  ///< a flight has ticked since the link started
  Nanos t = 0;
  bool has_state = false, has_phase = false, has_gnss = false, has_actuators = false, has_rc = false;
  msg::State state;
  msg::FlightPhase phase;
  msg::Gnss gnss;
  msg::Actuators actuators;
  msg::Rc rc;
};

struct Event {
  std::uint8_t severity;
  std::string text;
};

std::int32_t deg_e7(double deg) { return static_cast<std::int32_t>(std::llround(deg * 1e7)); }
std::int32_t mm(double m) { return static_cast<std::int32_t>(std::llround(m * 1000.0)); }
std::int16_t cm_s(double v) { return static_cast<std::int16_t>(std::clamp(std::lround(v * 100.0), -32767L, 32767L)); }
/// An angle in rad as centidegrees [0, 36000).
std::uint16_t cdeg(double rad) {
  double d = std::fmod(rad * 180.0 / kPi, 360.0);
  if (d < 0) d += 360.0;
  return static_cast<std::uint16_t>(std::lround(d * 100.0) % 36000);
}

bool airborne_phase(msg::Phase p) { return p != msg::Phase::preflight && p != msg::Phase::stopped; }

}  // namespace

void check_endpoint(const std::string& text, const std::string& what) { parse(text, what); }

struct GcsLink::Impl {
  Impl(Host& h, const GcsOptions& o)
      : host(h), options(o), socket(io), timer(io), configured_peer(parse(o.send_to, "--gcs")), table(numeric_params(h)) {
    const udp::endpoint local = parse(o.bind, "--gcs-bind");
    boost::system::error_code ec;
    socket.open(udp::v4(), ec);
    if (!ec) socket.bind(local, ec);
    if (ec) throw ConfigError("--gcs-bind " + o.bind + ": cannot bind the MAVLink port: " + ec.message());
    bound = socket.local_endpoint();
    for (const auto& t : host.topics()) topics.insert(t.name);
    start_mission_and_commands();
  }

  /// The mission protocol and the commands (mission_protocol.hpp, gcs_commands.hpp), answering through this link.
  void start_mission_and_commands() {
    const Outbox out{[this](std::uint32_t id, const std::vector<std::uint8_t>& payload) { send_frame(id, payload); },
                     [this](std::uint8_t severity, const std::string& text) {
                       say(StatusText{severity, text});
                     }};
    const auto dir =
        std::filesystem::temp_directory_path() / ("tern-mavlink-" + std::to_string(::getpid()) + "-" + std::to_string(bound.port()));
    watch = std::make_unique<FlightWatch>(host);
    mission = std::make_unique<MissionProtocol>(host, *watch, out, options.system_id, dir);
    commands = std::make_unique<GcsCommands>(host, *watch, *mission, out, options.system_id);
  }

  static std::vector<std::pair<std::string, ParamKind>> numeric_params(const Host& h) {
    std::vector<std::pair<std::string, ParamKind>> out;
    for (const auto& [name, p] : h.parameters()) out.emplace_back(name, p->kind());
    return out;
  }

  // ---- flight thread ----
  void observe(Nanos now) {
    if (now == 0) {  // a new flight
      next_snapshot = 0;
      last_phase.reset();
      handovers_seen = 0;
    }
    const auto& handovers = host.handovers();
    if (handovers.size() < handovers_seen) handovers_seen = 0;
    while (handovers_seen < handovers.size()) {
      const auto& h = handovers[handovers_seen++];
      push_event(MAV_SEVERITY_WARNING, "controller " + h.to + ": " + h.reason);
    }
    if (now < next_snapshot) return;
    next_snapshot = now + kSnapshotPeriod;
    Snapshot& s = staging;
    s.any = true;
    s.t = now;
    s.has_state = latest_message(host, "state", s.state);
    s.has_phase = latest_message(host, "flight_phase", s.phase);
    s.has_gnss = latest_message(host, "gnss", s.gnss);
    s.has_actuators = latest_message(host, "actuators", s.actuators);
    s.has_rc = latest_message(host, "rc", s.rc);
    if (s.has_phase && (!last_phase || *last_phase != s.phase.phase)) {
      last_phase = s.phase.phase;
      push_event(MAV_SEVERITY_INFO, "phase " + std::string(msg::phase_name(s.phase.phase)));
    }
    std::lock_guard lk(mu);
    latest = s;
  }

  void push_event(std::uint8_t severity, std::string text) {
    std::lock_guard lk(mu);
    if (events.size() < kMaxEvents) events.push_back({severity, std::move(text)});
  }

  // ---- the link's thread ----
  void start() {
    receive();
    schedule();
    thread = std::thread([this] { io.run(); });
  }

  void receive() {
    socket.async_receive_from(asio::buffer(rx), sender, [this](const boost::system::error_code& ec, std::size_t n) {
      if (ec == asio::error::operation_aborted) return;
      if (!ec) guarded([&] { on_datagram(n); });
      receive();
    });
  }

  void schedule() {
    timer.expires_after(kTick);
    timer.async_wait([this](const boost::system::error_code& ec) {
      if (ec) return;
      guarded([&] { on_tick(); });
      schedule();
    });
  }

  /// One bad request or failed send must not end the link: its error is one line, and the link
  /// goes on.
  template <class F>
  static void guarded(F&& f) {
    try {
      f();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "mavlink: %s\n", e.what());
    }
  }

  void on_datagram(std::size_t n) {
    std::vector<Frame> frames;
    {
      std::lock_guard lk(counters_mu);
      frames = parse_datagram(rx.data(), n, counters);
    }
    if (frames.empty()) return;
    heard(sender);
    for (const Frame& f : frames) {
      switch (f.msgid) {
        case PARAM_REQUEST_LIST: {
          const auto m = decode_param_request_list(f.payload);
          if (for_us(m.target_system, m.target_component)) list_cursor = 0;
          break;
        }
        case PARAM_REQUEST_READ: {
          const auto m = decode_param_request_read(f.payload);
          if (!for_us(m.target_system, m.target_component)) break;
          std::optional<std::size_t> i;
          if (m.param_index >= 0 && static_cast<std::size_t>(m.param_index) < table.params().size())
            i = static_cast<std::size_t>(m.param_index);
          else if (m.param_index < 0)
            i = table.find(m.param_id);
          if (i)
            send_param(*i);
          else
            say(StatusText{MAV_SEVERITY_WARNING, "no parameter " + (m.param_index >= 0 ? std::to_string(m.param_index) : m.param_id)});
          break;
        }
        case PARAM_SET: on_param_set(decode_param_set(f.payload)); break;
        default:  // missions, commands; else a GCS's HEARTBEAT (its address is kept above), our own messages echoed
          if (!mission->on_frame(f)) commands->on_frame(f);
          break;
      }
    }
  }

  bool for_us(std::uint8_t sys, std::uint8_t comp) const {
    return (sys == 0 || sys == options.system_id) && (comp == 0 || comp == MAV_COMP_ID_AUTOPILOT1);
  }

  void on_param_set(const ParamSet& m) {
    if (!for_us(m.target_system, m.target_component)) return;
    const auto i = table.find(m.param_id);
    if (!i) {
      say(StatusText{MAV_SEVERITY_WARNING, "no parameter " + m.param_id});
      return;
    }
    const MavParam& mp = table.params()[*i];
    const ParamBase* p = param(mp.qualified);
    std::optional<ParamValue> accepted;
    std::string why;
    if (p == nullptr) {
      why = mp.qualified + ": no longer in the mission (an instance was swapped)";
    } else if (!std::isfinite(m.param_value)) {
      why = mp.qualified + ": not a finite value";
    } else {
      try {
        const ParamValue v = p->validate(from_mav_value(m.param_value, mp.kind));  // throws ParamError
        host.request_param(mp.qualified, v, "mavlink");                            // throws: start-only in flight
        accepted = v;
      } catch (const std::exception& e) {
        why = e.what();
      }
    }
    if (accepted) {
      pending[mp.qualified] = {*accepted, Clock::now()};
      send_param(*i);
    } else {
      say(StatusText{MAV_SEVERITY_WARNING, why});
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
  ParamValue current(const std::string& qualified, const ParamBase& p) {
    const auto it = pending.find(qualified);
    if (it == pending.end()) return p.value();
    ParamValue now = p.value();
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
    ParamValueMsg v;
    v.param_id = mp.id;
    v.param_value = to_mav_value(current(mp.qualified, *p));
    v.param_type = mp.mav_type;
    v.param_count = static_cast<std::uint16_t>(table.params().size());
    v.param_index = static_cast<std::uint16_t>(i);
    send(v);
  }

  void heard(const udp::endpoint& from) {
    const auto now = Clock::now();
    for (auto it = peers.begin(); it != peers.end();) it = now - it->second > kPeerTimeout ? peers.erase(it) : std::next(it);
    if (peers.count(from) != 0 || peers.size() < kMaxPeers) peers[from] = now;
  }

  /// A text to the GCS, in chunks when it is longer than 50 characters.
  void say(const StatusText& t) {
    if (t.text.size() > 50 && ++text_id == 0) ++text_id;  // ids of chunked texts: 1, 2, ... (0: one chunk)
    for (const auto& chunk : statustext_chunks(t.severity, t.text, text_id)) send(chunk);
  }

  template <class M>
  void send(const M& m) {
    const auto bytes = encode(m);
    send_frame(msgid_of(m), bytes);
  }

  static std::uint32_t msgid_of(const Heartbeat&) { return HEARTBEAT; }
  static std::uint32_t msgid_of(const SysStatus&) { return SYS_STATUS; }
  static std::uint32_t msgid_of(const GpsRawInt&) { return GPS_RAW_INT; }
  static std::uint32_t msgid_of(const Attitude&) { return ATTITUDE; }
  static std::uint32_t msgid_of(const GlobalPositionInt&) { return GLOBAL_POSITION_INT; }
  static std::uint32_t msgid_of(const VfrHud&) { return VFR_HUD; }
  static std::uint32_t msgid_of(const HomePosition&) { return HOME_POSITION; }
  static std::uint32_t msgid_of(const ParamValueMsg&) { return PARAM_VALUE; }
  static std::uint32_t msgid_of(const StatusText&) { return STATUSTEXT; }

  void send_frame(std::uint32_t msgid, const std::vector<std::uint8_t>& payload) {
    const auto frame = encode_frame(msgid, payload, seq++, options.system_id, MAV_COMP_ID_AUTOPILOT1);
    boost::system::error_code ec;
    socket.send_to(asio::buffer(frame), configured_peer, 0, ec);  // nobody listening: nothing to do
    for (const auto& [peer, when] : peers)
      if (peer != configured_peer) socket.send_to(asio::buffer(frame), peer, 0, ec);
  }

  /// Every `period` of wall time, from the link's start.
  bool due(Clock::time_point& next, std::chrono::milliseconds period, Clock::time_point now) {
    if (now < next) return false;
    next = std::max(next + period, now);
    return true;
  }

  void on_tick() {
    const auto now = Clock::now();
    Snapshot s;
    std::deque<Event> ev;
    {
      std::lock_guard lk(mu);
      s = latest;
      ev.swap(events);
    }
    for (const auto& e : ev) say(StatusText{e.severity, e.text});
    if (due(next_heartbeat, std::chrono::milliseconds(1000), now)) {
      send(heartbeat(s));
      send(sys_status(s));
    }
    const bool state = s.has_state && s.state.valid && s.state.origin_valid;
    if (state && due(next_attitude, std::chrono::milliseconds(50), now)) send(attitude(s));
    if (state && due(next_position, std::chrono::milliseconds(200), now)) send(global_position(s));
    if (s.has_state && due(next_hud, std::chrono::milliseconds(250), now)) send(vfr_hud(s));
    if (s.has_gnss && due(next_gps, std::chrono::milliseconds(500), now)) send(gps_raw(s));
    if (s.has_state && s.state.origin_valid && due(next_home, std::chrono::milliseconds(2000), now)) send(home(s));
    for (std::size_t k = 0; k < kParamsPerTick && list_cursor && *list_cursor < table.params().size(); ++k) send_param((*list_cursor)++);
    if (list_cursor && *list_cursor >= table.params().size()) list_cursor.reset();
    mission->on_tick();
  }

  // ---- the messages (the mapping: docs/ground-station.md) ----
  Heartbeat heartbeat(const Snapshot& s) const {
    Heartbeat h;
    h.type = MAV_TYPE_FIXED_WING;
    h.autopilot = MAV_AUTOPILOT_GENERIC;
    const bool flying = host.flying();
    if (!s.any || !s.has_phase) {
      h.system_status = s.any && flying ? MAV_STATE_BOOT : MAV_STATE_STANDBY;
      return h;
    }
    h.custom_mode = static_cast<std::uint32_t>(s.phase.phase);  // tern's Phase code (tern/msg/phase.hpp)
    h.base_mode = MAV_MODE_FLAG_CUSTOM_MODE_ENABLED;
    const bool armed = flying && airborne_phase(s.phase.phase);
    if (armed) {
      h.base_mode |= MAV_MODE_FLAG_SAFETY_ARMED;
      if (s.has_rc && s.rc.rc_override)
        h.base_mode |= MAV_MODE_FLAG_MANUAL_INPUT_ENABLED;
      else
        h.base_mode |= MAV_MODE_FLAG_STABILIZE_ENABLED | MAV_MODE_FLAG_GUIDED_ENABLED | MAV_MODE_FLAG_AUTO_ENABLED;
    }
    h.system_status = !armed ? MAV_STATE_STANDBY : (s.has_rc && s.rc.failsafe) ? MAV_STATE_CRITICAL : MAV_STATE_ACTIVE;
    return h;
  }

  SysStatus sys_status(const Snapshot& s) const {
    SysStatus m;
    const auto has = [this](const char* t) { return topics.count(t) != 0; };
    std::uint32_t present = 0, unhealthy = 0;
    const std::uint8_t degraded = s.has_state ? s.state.degraded_sensors : 0;
    const auto sensor = [&](const char* topic, std::uint32_t bits, std::uint8_t sensor_bit) {
      if (!has(topic)) return;
      present |= bits;
      if ((degraded & sensor_bit) != 0) unhealthy |= bits;
    };
    sensor("imu", MAV_SYS_STATUS_SENSOR_3D_GYRO | MAV_SYS_STATUS_SENSOR_3D_ACCEL, msg::sensor_bit::imu);
    sensor("mag", MAV_SYS_STATUS_SENSOR_3D_MAG, msg::sensor_bit::mag);
    sensor("baro", MAV_SYS_STATUS_SENSOR_ABSOLUTE_PRESSURE, msg::sensor_bit::baro);
    sensor("diff_pressure", MAV_SYS_STATUS_SENSOR_DIFFERENTIAL_PRESSURE, msg::sensor_bit::diff_pressure);
    sensor("gnss", MAV_SYS_STATUS_SENSOR_GPS, msg::sensor_bit::gnss);
    if (has("state")) {
      present |= MAV_SYS_STATUS_AHRS;
      if (!s.has_state || !s.state.valid) unhealthy |= MAV_SYS_STATUS_AHRS;
    }
    if (has("actuators"))
      present |= MAV_SYS_STATUS_SENSOR_ANGULAR_RATE_CONTROL | MAV_SYS_STATUS_SENSOR_ATTITUDE_STABILIZATION |
                 MAV_SYS_STATUS_SENSOR_YAW_POSITION | MAV_SYS_STATUS_SENSOR_Z_ALTITUDE_CONTROL | MAV_SYS_STATUS_SENSOR_XY_POSITION_CONTROL;
    if (has("rc")) {
      present |= MAV_SYS_STATUS_SENSOR_RC_RECEIVER;
      if (s.has_rc && s.rc.failsafe) unhealthy |= MAV_SYS_STATUS_SENSOR_RC_RECEIVER;
    }
    m.present = present;
    m.enabled = present;
    m.health = present & ~unhealthy;
    Counters c;
    {
      std::lock_guard lk(counters_mu);
      c = counters;
    }
    const std::uint64_t seen = c.frames + c.dropped();
    m.drop_rate_comm = seen == 0 ? 0 : static_cast<std::uint16_t>(std::min<std::uint64_t>(10000, c.dropped() * 10000 / seen));
    m.errors_comm = static_cast<std::uint16_t>(std::min<std::uint64_t>(UINT16_MAX, c.dropped()));
    return m;
  }

  static std::uint32_t boot_ms(const Snapshot& s) { return static_cast<std::uint32_t>(s.t / 1'000'000); }

  Attitude attitude(const Snapshot& s) const {
    const auto& x = s.state;
    return {boot_ms(s),
            static_cast<float>(x.phi),
            static_cast<float>(x.theta),
            static_cast<float>(x.psi),
            static_cast<float>(x.p),
            static_cast<float>(x.q),
            static_cast<float>(x.r)};
  }

  GeoPoint position(const msg::State& x) {
    const GeoPoint o{x.origin_lat, x.origin_lon, x.origin_alt};
    if (!origin || origin->origin() != o) origin.emplace(o);
    return origin->to_geodetic(Eigen::Vector3d(x.p_n, x.p_e, x.p_d));
  }

  GlobalPositionInt global_position(const Snapshot& s) {
    const auto& x = s.state;
    const GeoPoint g = position(x);
    GlobalPositionInt m;
    m.time_boot_ms = boot_ms(s);
    m.lat = deg_e7(g.lat);
    m.lon = deg_e7(g.lon);
    m.alt = mm(g.alt);
    m.relative_alt = mm(-x.p_d);  // home is the estimate's origin
    m.vx = cm_s(x.v_n);
    m.vy = cm_s(x.v_e);
    m.vz = cm_s(x.v_d);
    m.hdg = cdeg(x.psi);
    return m;
  }

  VfrHud vfr_hud(const Snapshot& s) const {
    const auto& x = s.state;
    VfrHud m;
    m.airspeed = static_cast<float>(x.Va);
    m.groundspeed = static_cast<float>(x.Vg);
    m.alt = static_cast<float>(x.origin_alt - x.p_d);
    m.climb = static_cast<float>(-x.v_d);
    m.heading = static_cast<std::int16_t>(cdeg(x.psi) / 100);
    m.throttle = s.has_actuators ? static_cast<std::uint16_t>(std::lround(std::clamp(s.actuators.delta_t, 0.0, 1.0) * 100.0)) : 0;
    return m;
  }

  GpsRawInt gps_raw(const Snapshot& s) const {
    const auto& g = s.gnss;
    GpsRawInt m;
    m.time_usec = static_cast<std::uint64_t>(g.stamp / 1000);
    switch (g.fix_type) {
      case msg::FixType::none:
      case msg::FixType::dead_reckoning: m.fix_type = GPS_FIX_TYPE_NO_FIX; break;
      case msg::FixType::fix_2d: m.fix_type = GPS_FIX_TYPE_2D_FIX; break;
      case msg::FixType::fix_3d: m.fix_type = GPS_FIX_TYPE_3D_FIX; break;
    }
    m.lat = deg_e7(g.lat);
    m.lon = deg_e7(g.lon);
    m.alt = mm(g.alt);
    const double v = std::hypot(g.vel.x(), g.vel.y());
    m.vel = static_cast<std::uint16_t>(std::min(65534L, std::lround(v * 100.0)));
    m.cog = v > 0.5 ? cdeg(std::atan2(g.vel.y(), g.vel.x())) : UINT16_MAX;  // below 0.5 m/s the course is noise
    m.satellites_visible = g.num_sats;
    return m;
  }

  HomePosition home(const Snapshot& s) const {
    HomePosition m;
    m.latitude = deg_e7(s.state.origin_lat);
    m.longitude = deg_e7(s.state.origin_lon);
    m.altitude = mm(s.state.origin_alt);
    return m;  // x y z 0: home is the local frame's origin; q identity and no approach vector
  }

  Host& host;
  GcsOptions options;
  asio::io_context io;
  udp::socket socket;
  asio::steady_timer timer;
  udp::endpoint configured_peer, bound, sender;
  std::array<std::uint8_t, 2048> rx{};
  ParamTable table;
  std::set<std::string> topics;
  std::thread thread;
  int observer_id = 0;
  std::unique_ptr<FlightWatch> watch;
  std::unique_ptr<MissionProtocol> mission;
  std::unique_ptr<GcsCommands> commands;

  // flight thread only
  Nanos next_snapshot = 0;
  Snapshot staging;
  std::optional<msg::Phase> last_phase;
  std::size_t handovers_seen = 0;

  // under mu
  std::mutex mu;
  Snapshot latest;
  std::deque<Event> events;

  // under counters_mu
  mutable std::mutex counters_mu;
  Counters counters;

  // the link's thread only
  std::map<udp::endpoint, Clock::time_point> peers;
  std::optional<std::size_t> list_cursor;
  std::map<std::string, std::pair<ParamValue, Clock::time_point>> pending;  // accepted sets not yet applied
  std::uint8_t seq = 0;
  std::uint16_t text_id = 0;
  std::optional<GeoOrigin> origin;
  Clock::time_point next_heartbeat{}, next_attitude{}, next_position{}, next_hud{}, next_gps{}, next_home{};
};

GcsLink::GcsLink(Host& host, const GcsOptions& options) : impl_(std::make_unique<Impl>(host, options)) {
  Impl* impl = impl_.get();
  impl->observer_id = host.add_tick_observer([impl](Nanos now) { impl->observe(now); });
  impl->start();
}

GcsLink::~GcsLink() {
  impl_->host.remove_tick_observer(impl_->observer_id);
  // io.stop() makes run() return once the handler running now (if any) is done, whatever else is
  // queued: cancelling the timer and closing the socket from a posted handler did not always end
  // it, as a tick or a datagram already completed re-armed itself (mavlink_flood hung under load)
  impl_->io.stop();
  impl_->thread.join();
}

std::string GcsLink::describe() const {
  std::string out =
      "udp " + impl_->bound.address().to_string() + ":" + std::to_string(impl_->bound.port()) + " -> " + impl_->options.send_to;
  out += ", " + std::to_string(impl_->table.params().size()) + " parameters";
  return out;
}

std::vector<std::pair<std::string, std::string>> GcsLink::shortened_ids() const { return impl_->table.shortened(); }

Counters GcsLink::counters() const {
  std::lock_guard lk(impl_->counters_mu);
  return impl_->counters;
}

}  // namespace tern::core::mavlink
