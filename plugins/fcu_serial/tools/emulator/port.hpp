// emulator/port.hpp: the emulator's end of the link: a pseudo-terminal's master side, or a
// UDP socket (the ROSflight SIL ports).
#pragma once

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <utility>  // before Asio: Boost 1.74's awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>

namespace tern::fcu::emulator {

/// The port: a pseudo-terminal's master side, a UDP socket, or an inherited stream socket.
class Port {
 public:
  virtual ~Port() = default;
  virtual int fd() const = 0;
  virtual std::size_t read(std::uint8_t* buf, std::size_t n) = 0;  ///< 0 if nothing
  virtual bool write(const std::uint8_t* p, std::size_t n) = 0;    ///< false if dropped
};

/// Writes all n bytes to a non-blocking descriptor; a reader that does not drain it for 50 ms
/// (as a UART would not wait) drops the rest: false.
inline bool write_all(int fd, const std::uint8_t* p, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN) {  // nobody reads: wait a little, as a UART would not, then drop
        pollfd pf{fd, POLLOUT, 0};
        if (poll(&pf, 1, 50) > 0) continue;
      }
      return false;
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

class PtyPort final : public Port {
 public:
  PtyPort() {
    if (openpty(&master_, &slave_, name_, nullptr, nullptr) != 0)
      throw std::runtime_error(std::string("openpty failed: ") + std::strerror(errno));
    termios t{};
    tcgetattr(slave_, &t);
    cfmakeraw(&t);
    cfsetispeed(&t, B921600);
    cfsetospeed(&t, B921600);
    tcsetattr(slave_, TCSANOW, &t);
    fcntl(master_, F_SETFL, fcntl(master_, F_GETFL) | O_NONBLOCK);
  }
  ~PtyPort() override {
    close(master_);
    close(slave_);
  }
  const char* name() const { return name_; }
  int fd() const override { return master_; }
  std::size_t read(std::uint8_t* buf, std::size_t n) override {
    const ssize_t r = ::read(master_, buf, n);
    return r > 0 ? static_cast<std::size_t>(r) : 0;
  }
  bool write(const std::uint8_t* p, std::size_t n) override { return write_all(master_, p, n); }

 private:
  int master_ = -1, slave_ = -1;
  char name_[256] = {};
};

/// An inherited, connected stream socket (a byte stream like the pseudo-terminal, without the
/// terminal layer: fcu_serial's lockstep link).
class FdPort final : public Port {
 public:
  explicit FdPort(int fd) : fd_(fd) {
    if (fcntl(fd_, F_SETFL, fcntl(fd_, F_GETFL) | O_NONBLOCK) != 0)
      throw std::runtime_error("--fd " + std::to_string(fd) + ": not an open file descriptor: " + std::strerror(errno));
  }
  ~FdPort() override { close(fd_); }
  int fd() const override { return fd_; }
  std::size_t read(std::uint8_t* buf, std::size_t n) override {
    const ssize_t r = ::read(fd_, buf, n);
    return r > 0 ? static_cast<std::size_t>(r) : 0;
  }
  bool write(const std::uint8_t* p, std::size_t n) override { return write_all(fd_, p, n); }

 private:
  int fd_;
};

class UdpPort final : public Port {
 public:
  UdpPort(const std::string& host, unsigned bind_port, unsigned remote_port) : sock_(io_) {
    namespace asio = boost::asio;
    const auto addr = asio::ip::make_address(host);
    sock_.open(addr.is_v4() ? asio::ip::udp::v4() : asio::ip::udp::v6());
    sock_.set_option(asio::socket_base::reuse_address(true));
    sock_.bind({addr, static_cast<unsigned short>(bind_port)});
    sock_.non_blocking(true);
    remote_ = {addr, static_cast<unsigned short>(remote_port)};
  }
  int fd() const override { return const_cast<boost::asio::ip::udp::socket&>(sock_).native_handle(); }
  std::size_t read(std::uint8_t* buf, std::size_t n) override {
    boost::system::error_code ec;
    boost::asio::ip::udp::endpoint from;
    const std::size_t r = sock_.receive_from(boost::asio::buffer(buf, n), from, 0, ec);
    return ec ? 0 : r;
  }
  bool write(const std::uint8_t* p, std::size_t n) override {
    boost::system::error_code ec;
    sock_.send_to(boost::asio::buffer(p, n), remote_, 0, ec);
    return !ec;
  }

 private:
  boost::asio::io_context io_;
  boost::asio::ip::udp::socket sock_;
  boost::asio::ip::udp::endpoint remote_;
};

}  // namespace tern::fcu::emulator
