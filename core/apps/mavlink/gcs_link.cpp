// core/apps/mavlink/gcs_link.cpp: the MAVLink ground-station endpoint (gcs_link.hpp): the socket,
// the peers, the counts and the routing by target system; each vehicle's side is gcs_vehicle.cpp.
#include "mavlink/gcs_link.hpp"

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

#include <unistd.h>

#include <boost/asio.hpp>

#include "config/error.hpp"
#include "flight/host.hpp"
#include "mavlink/gcs_vehicle.hpp"

namespace tern::core::mavlink {
namespace {

namespace asio = boost::asio;
using udp = asio::ip::udp;
using Clock = std::chrono::steady_clock;

constexpr std::size_t kMaxPeers = 8;
constexpr auto kPeerTimeout = std::chrono::seconds(10);
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

}  // namespace

void check_endpoint(const std::string& text, const std::string& what) { parse(text, what); }

struct GcsLink::Impl {
  Impl(const std::vector<LinkedVehicle>& linked, const GcsOptions& o)
      : options(o), socket(io), timer(io), configured_peer(parse(o.send_to, "--gcs")) {
    const udp::endpoint local = parse(o.bind, "--gcs-bind");
    boost::system::error_code ec;
    socket.open(udp::v4(), ec);
    if (!ec) socket.bind(local, ec);
    if (ec) throw ConfigError("--gcs-bind " + o.bind + ": cannot bind the MAVLink port: " + ec.message());
    bound = socket.local_endpoint();
    std::set<std::uint8_t> ids;
    for (const LinkedVehicle& v : linked) {
      if (v.system_id == 0 || !ids.insert(v.system_id).second)
        throw ConfigError("--gcs: vehicle " + v.name + ": MAVLink system id " + std::to_string(v.system_id) +
                          (v.system_id == 0 ? " is not 1-255" : " is another vehicle's"));
      names.push_back(v.name);
      vehicles.push_back(std::make_unique<GcsVehicle>(
          *v.host, v.system_id, [this](const std::vector<std::uint8_t>& f) { send(f); }, upload_dir(v.system_id)));
    }
  }

  /// Where vehicle `system_id`'s accepted mission uploads are written (mission_protocol.hpp).
  std::filesystem::path upload_dir(std::uint8_t system_id) const {
    return std::filesystem::temp_directory_path() /
           ("tern-mavlink-" + std::to_string(::getpid()) + "-" + std::to_string(bound.port()) + "-" + std::to_string(system_id));
  }

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
      const Counters c = link_counters();
      for (auto& v : vehicles) guarded([&] { v->on_tick(c); });
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
    for (const Frame& f : frames) route(f);
  }

  /// To the vehicle the frame's target_system names, to every vehicle for 0 or no target
  /// (MAVLink's routing); for a system no vehicle has: counted and ignored.
  void route(const Frame& f) {
    const std::optional<std::uint8_t> to = target_system(f);
    bool taken = false;
    for (auto& v : vehicles) {
      if (to && *to != 0 && *to != v->system_id()) continue;
      taken = true;
      guarded([&] { v->on_frame(f); });
    }
    if (taken) return;
    std::lock_guard lk(counters_mu);
    ++counters.other_system;
  }

  void heard(const udp::endpoint& from) {
    const auto now = Clock::now();
    for (auto it = peers.begin(); it != peers.end();) it = now - it->second > kPeerTimeout ? peers.erase(it) : std::next(it);
    if (peers.count(from) != 0 || peers.size() < kMaxPeers) peers[from] = now;
  }

  Counters link_counters() const {
    std::lock_guard lk(counters_mu);
    return counters;
  }

  /// A vehicle's frame to the configured GCS address and to every peer heard.
  void send(const std::vector<std::uint8_t>& frame) {
    boost::system::error_code ec;
    socket.send_to(asio::buffer(frame), configured_peer, 0, ec);  // nobody listening: nothing to do
    for (const auto& [peer, when] : peers)
      if (peer != configured_peer) socket.send_to(asio::buffer(frame), peer, 0, ec);
  }

  GcsOptions options;
  asio::io_context io;
  udp::socket socket;
  asio::steady_timer timer;
  udp::endpoint configured_peer, bound, sender;
  std::array<std::uint8_t, 2048> rx{};
  std::thread thread;
  std::vector<std::string> names;                     // the vehicles', in order
  std::vector<std::unique_ptr<GcsVehicle>> vehicles;  // run on the link's thread (observe: the flight thread)
  std::vector<int> observer_ids;

  // under counters_mu
  mutable std::mutex counters_mu;
  Counters counters;

  // the link's thread only
  std::map<udp::endpoint, Clock::time_point> peers;
};

GcsLink::GcsLink(const std::vector<LinkedVehicle>& vehicles, const GcsOptions& options) : impl_(std::make_unique<Impl>(vehicles, options)) {
  for (auto& v : impl_->vehicles) {
    GcsVehicle* vehicle = v.get();
    impl_->observer_ids.push_back(vehicle->host().add_tick_observer([vehicle](Nanos now) { vehicle->observe(now); }));
  }
  impl_->start();
}

GcsLink::~GcsLink() {
  for (std::size_t i = 0; i < impl_->observer_ids.size(); ++i) impl_->vehicles[i]->host().remove_tick_observer(impl_->observer_ids[i]);
  // io.stop() makes run() return once the handler running now (if any) is done, whatever else is
  // queued: cancelling the timer and closing the socket from a posted handler did not always end
  // it, as a tick or a datagram already completed re-armed itself (mavlink_flood hung under load)
  impl_->io.stop();
  impl_->thread.join();
}

std::string GcsLink::describe() const {
  const Impl& m = *impl_;
  std::string out = "udp " + m.bound.address().to_string() + ":" + std::to_string(m.bound.port()) + " -> " + m.options.send_to;
  if (m.vehicles.size() == 1) return out + ", " + std::to_string(m.vehicles[0]->param_count()) + " parameters";
  for (std::size_t i = 0; i < m.vehicles.size(); ++i)
    out += (i == 0 ? ", systems " : ", ") + std::to_string(m.vehicles[i]->system_id()) + " " + m.names[i] + " (" +
           std::to_string(m.vehicles[i]->param_count()) + " parameters)";
  return out;
}

std::vector<std::pair<std::string, std::string>> GcsLink::shortened_ids() const {
  return impl_->vehicles.empty() ? std::vector<std::pair<std::string, std::string>>{} : impl_->vehicles.front()->shortened_ids();
}

Counters GcsLink::counters() const { return impl_->link_counters(); }

}  // namespace tern::core::mavlink
