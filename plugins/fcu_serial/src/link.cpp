// link.cpp: see tern_fcu_serial/link.hpp.
#include "tern_fcu_serial/link.hpp"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <deque>
#include <stdexcept>

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <utility>  // before Asio: Boost 1.74's awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>

namespace tern::fcu {

namespace asio = boost::asio;
using boost::system::error_code;

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string LinkOptions::describe() const {
  if (kind == Kind::serial) return "serial " + device + " @ " + std::to_string(baud);
  if (kind == Kind::socket) return "socket (fd " + std::to_string(socket_fd) + ")";
  return "udp " + udp_host + ":" + std::to_string(udp_bind_port) + " -> " + std::to_string(udp_remote_port);
}

struct Link::Impl {
  Link& link;
  asio::io_context io;
  asio::executor_work_guard<asio::io_context::executor_type> work{io.get_executor()};
  asio::serial_port serial{io};
  asio::ip::udp::socket udp{io};
  asio::local::stream_protocol::socket local{io};
  asio::ip::udp::endpoint remote, sender;
  asio::steady_timer reopen_timer{io};
  std::array<std::uint8_t, 4096> buf{};
  mavlink::Parser parser;
  bool open = false;
  bool reported_down = false;
  bool stopping = false;  ///< set by stop(): a reopen already due must not open the port again

  explicit Impl(Link& l) : link(l) {}

  /// Opens the port; throws std::runtime_error naming it.
  void open_port() {
    const LinkOptions& o = link.opt_;
    error_code ec;
    if (o.kind == LinkOptions::Kind::serial) {
      serial.open(o.device, ec);
      if (ec) throw std::runtime_error("cannot open " + o.describe() + ": " + ec.message());
      serial.set_option(asio::serial_port_base::baud_rate(o.baud), ec);
      if (!ec) serial.set_option(asio::serial_port_base::character_size(8), ec);
      if (!ec) serial.set_option(asio::serial_port_base::parity(asio::serial_port_base::parity::none), ec);
      if (!ec) serial.set_option(asio::serial_port_base::stop_bits(asio::serial_port_base::stop_bits::one), ec);
      if (!ec) serial.set_option(asio::serial_port_base::flow_control(asio::serial_port_base::flow_control::none), ec);
      if (ec) {
        serial.close(ec);
        throw std::runtime_error("cannot configure " + o.describe() + ": " + ec.message());
      }
    } else if (o.kind == LinkOptions::Kind::socket) {
      const int fd = ::dup(o.socket_fd);
      if (fd < 0) throw std::runtime_error("cannot use " + o.describe() + ": " + std::strerror(errno));
      local.assign(asio::local::stream_protocol(), fd, ec);
      if (ec) {
        ::close(fd);
        throw std::runtime_error("cannot use " + o.describe() + ": " + ec.message());
      }
    } else {
      const auto addr = asio::ip::make_address(o.udp_host, ec);
      if (ec) throw std::runtime_error("udp host '" + o.udp_host + "' is not an IP address: " + ec.message());
      udp.open(addr.is_v4() ? asio::ip::udp::v4() : asio::ip::udp::v6(), ec);
      if (!ec) udp.set_option(asio::socket_base::reuse_address(true), ec);
      if (!ec) udp.bind(asio::ip::udp::endpoint(addr, static_cast<unsigned short>(o.udp_bind_port)), ec);
      if (ec) {
        udp.close(ec);
        throw std::runtime_error("cannot bind " + o.describe() + ": " + ec.message());
      }
      remote = asio::ip::udp::endpoint(addr, static_cast<unsigned short>(o.udp_remote_port));
    }
    open = true;
    parser.reset();
    read();
  }

  void close_port() {
    error_code ec;  // a pending write completes with operation_aborted and clears the queue
    if (serial.is_open()) serial.close(ec);
    if (udp.is_open()) udp.close(ec);
    if (local.is_open()) local.close(ec);
    open = false;
  }

  void event(std::string s) {
    std::lock_guard lk(link.mu_);
    link.events_.push_back(std::move(s));
  }

  void on_error(const std::string& what, const error_code& ec) {
    if (!open) return;
    close_port();
    event(link.opt_.describe() + ": " + what + " (" + ec.message() + "); reopening every " +
          std::to_string(link.opt_.reopen_interval / 1'000'000) + " ms");
    schedule_reopen();
  }

  void schedule_reopen() {
    reopen_timer.expires_after(std::chrono::nanoseconds(link.opt_.reopen_interval));
    reopen_timer.async_wait([this](const error_code& ec) {
      if (ec || stopping) return;  // cancelled, or due just before stop()
      try {
        open_port();
        {
          std::lock_guard lk(link.mu_);
          ++link.stats_.reopens;
        }
        event(link.opt_.describe() + ": reopened");
      } catch (const std::exception&) {
        schedule_reopen();
      }
    });
  }

  void read() {
    auto handler = [this](const error_code& ec, std::size_t n) {
      if (ec) {
        if (ec == asio::error::operation_aborted) return;
        on_error("read failed", ec);
        return;
      }
      const std::int64_t now = steady_ns();
      std::size_t added = 0;
      {
        std::lock_guard lk(link.mu_);
        parser.feed(buf.data(), n, [&](const mavlink::Frame& f) {
          if (link.queue_.size() >= link.opt_.queue_capacity) {
            link.queue_.pop_front();
            ++link.stats_.queue_dropped;
          }
          link.queue_.push_back(Received{f, now});
          ++added;
        });
        link.stats_.parser = parser.stats();
      }
      if (added) link.cv_.notify_all();
      read();
    };
    if (link.opt_.kind == LinkOptions::Kind::serial)
      serial.async_read_some(asio::buffer(buf), handler);
    else if (link.opt_.kind == LinkOptions::Kind::socket)
      local.async_read_some(asio::buffer(buf), handler);
    else
      udp.async_receive_from(asio::buffer(buf), sender, handler);
  }

  // Writes go out one at a time, asynchronously, so that stop() never waits on a port that
  // does not drain (an FCU that stopped reading). At most kMaxQueuedWrites wait; beyond that the
  // oldest is dropped and counted as a write error.
  static constexpr std::size_t kMaxQueuedWrites = 256;
  std::deque<std::vector<std::uint8_t>> writes;
  bool writing = false;

  void write(std::vector<std::uint8_t> bytes) {
    if (!open) return;
    if (writes.size() >= kMaxQueuedWrites) {
      writes.erase(writes.begin() + (writing ? 1 : 0));  // never the one being written
      std::lock_guard lk(link.mu_);
      ++link.stats_.write_errors;
    }
    writes.push_back(std::move(bytes));
    if (!writing) write_next();
  }

  void write_next() {
    if (writes.empty() || !open) {
      writing = false;
      return;
    }
    writing = true;
    auto done = [this](const error_code& ec, std::size_t n) {
      writing = false;
      if (ec == asio::error::operation_aborted) {
        writes.clear();
        return;
      }
      {
        std::lock_guard lk(link.mu_);
        if (ec)
          ++link.stats_.write_errors;
        else
          link.stats_.bytes_sent += n;
      }
      if (!writes.empty()) writes.pop_front();
      // UDP: the FCU not listening yet (connection refused) is not a link failure.
      if (ec && link.opt_.kind != LinkOptions::Kind::udp) {
        writes.clear();
        on_error("write failed", ec);
        return;
      }
      write_next();
    };
    if (link.opt_.kind == LinkOptions::Kind::serial)
      asio::async_write(serial, asio::buffer(writes.front()), done);
    else if (link.opt_.kind == LinkOptions::Kind::socket)
      asio::async_write(local, asio::buffer(writes.front()), done);
    else
      udp.async_send_to(asio::buffer(writes.front()), remote, done);
  }
};

Link::Link(LinkOptions o) : opt_(std::move(o)) {}

Link::~Link() { stop(); }

void Link::start() {
  if (thread_.joinable()) return;
  impl_ = std::make_unique<Impl>(*this);
  impl_->open_port();  // throws: nothing to clean up, no thread yet
  thread_ = std::thread([this] { impl_->io.run(); });
}

void Link::stop() {
  if (!impl_) return;
  asio::post(impl_->io, [this] {
    impl_->stopping = true;
    impl_->reopen_timer.cancel();
    impl_->close_port();
    impl_->work.reset();
  });
  if (thread_.joinable()) thread_.join();
  impl_.reset();
}

void Link::send(std::vector<std::uint8_t> bytes) {
  if (!impl_) return;
  if (opt_.kind == LinkOptions::Kind::socket) {
    send_now(bytes);
    return;
  }
  asio::post(impl_->io, [this, b = std::move(bytes)]() mutable { impl_->write(std::move(b)); });
}

/// A local socket is written from the caller's thread (no hand-over to the link thread: in
/// lockstep that hand-over is a thread wake-up per IMU sample); a peer that does not drain it
/// for 50 ms loses the rest (counted), as a UART would not wait.
void Link::send_now(const std::vector<std::uint8_t>& bytes) {
  std::lock_guard wl(write_mu_);
  const std::uint8_t* p = bytes.data();
  std::size_t n = bytes.size();
  while (n > 0) {
    const ssize_t w = ::send(opt_.socket_fd, p, n, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w < 0 && errno == EAGAIN) {
      pollfd pf{opt_.socket_fd, POLLOUT, 0};
      if (poll(&pf, 1, 50) > 0) continue;
    }
    if (w < 0) break;
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  std::lock_guard lk(mu_);
  if (n > 0)
    ++stats_.write_errors;
  else
    stats_.bytes_sent += bytes.size();
}

std::size_t Link::drain(std::deque<Received>& out) {
  std::lock_guard lk(mu_);
  const std::size_t n = queue_.size();
  for (auto& r : queue_) out.push_back(r);
  queue_.clear();
  return n;
}

bool Link::wait(std::int64_t timeout_ns) {
  std::unique_lock lk(mu_);
  return cv_.wait_for(lk, std::chrono::nanoseconds(timeout_ns), [this] { return !queue_.empty(); });
}

std::vector<std::string> Link::take_events() {
  std::lock_guard lk(mu_);
  std::vector<std::string> e;
  e.swap(events_);
  return e;
}

LinkStats Link::stats() const {
  std::lock_guard lk(mu_);
  return stats_;
}

}  // namespace tern::fcu
