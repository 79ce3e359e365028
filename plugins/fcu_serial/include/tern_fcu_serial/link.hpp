// tern_fcu_serial/link.hpp: the byte link to a ROSflight FCU (serial port, UDP, or a connected
// local stream socket to an FCU program started by the plugin) with a reader thread. Plain C++ (Boost.Asio), no tern host types.
//
// start() opens the port (throws std::runtime_error with one line naming the device or port if
// that fails) and starts one thread that reads, parses (mavlink::Parser) and queues valid frames
// with their arrival time (steady clock, ns) in a bounded queue; when the queue is full the
// oldest frame is dropped and counted. Writes (send()) are posted to that thread, so the caller
// never blocks on the port. A read or write error closes the port and reopens it every
// `reopen_interval` until it works; what happened is queued as text events (take_events()) for
// the caller to log. A local socket (Kind::socket: an FCU program the plugin started) is
// written in the caller's thread instead: in lockstep a hand-over to the link thread per IMU
// sample cost a fifth of the step. stop() (and the destructor) stops and joins the thread and
// closes the port.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "tern_fcu_serial/codec.hpp"

namespace tern::fcu {

struct LinkOptions {
  enum class Kind { serial, udp, socket };
  Kind kind = Kind::serial;
  std::string device = "/dev/ttyACM0";  ///< serial device (or pseudo-terminal)
  unsigned baud = 921600;               ///< serial baud rate
  std::string udp_host = "127.0.0.1";   ///< where both ends live (ROSflight SIL: localhost)
  unsigned udp_bind_port = 14520;       ///< our port (rosflight_io's default)
  unsigned udp_remote_port = 14525;     ///< the FCU's port (ROSflight SIL firmware's default)
  /// Kind::socket: a connected AF_UNIX stream socket (the other end handed to the FCU program);
  /// the link uses a duplicate and never closes this one.
  int socket_fd = -1;
  std::size_t queue_capacity = 8192;           ///< frames
  std::int64_t reopen_interval = 500'000'000;  ///< ns
  /// One line naming the port, for messages: "serial /dev/ttyACM0 @ 921600", "udp 127.0.0.1:14520"
  /// or "socket (fd 7)".
  std::string describe() const;
};

struct Received {
  mavlink::Frame frame;
  std::int64_t rx_ns = 0;  ///< steady-clock arrival time
};

struct LinkStats {
  mavlink::ParserStats parser;
  std::uint64_t queue_dropped = 0;  ///< frames dropped because the queue was full
  std::uint64_t bytes_sent = 0;
  std::uint64_t write_errors = 0;
  std::uint64_t reopens = 0;
};

/// Steady-clock time in ns (the clock of Received::rx_ns).
std::int64_t steady_ns();

class Link {
 public:
  explicit Link(LinkOptions o);
  ~Link();
  Link(const Link&) = delete;
  Link& operator=(const Link&) = delete;

  void start();
  void stop();
  bool running() const { return thread_.joinable(); }

  /// Queues bytes for writing (thread-safe, never blocks on the port). Dropped while the port is closed.
  void send(std::vector<std::uint8_t> bytes);
  /// Moves every queued frame to `out` (appending); returns how many.
  std::size_t drain(std::deque<Received>& out);
  /// Waits until a frame is queued or `timeout_ns` passes; true if frames are queued.
  bool wait(std::int64_t timeout_ns);
  std::vector<std::string> take_events();
  LinkStats stats() const;
  const LinkOptions& options() const { return opt_; }

 private:
  struct Impl;
  LinkOptions opt_;
  std::unique_ptr<Impl> impl_;
  std::thread thread_;
  void send_now(const std::vector<std::uint8_t>& bytes);
  std::mutex write_mu_;  ///< Kind::socket: writes from the callers' threads, one at a time
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<Received> queue_;
  std::vector<std::string> events_;
  LinkStats stats_;
  friend struct Impl;
};

}  // namespace tern::fcu
