// emulator/uart.hpp: `--baud N`: the FCU program's port paced as a UART at N baud, 8N1.
//
// A pseudo-terminal (or a local socket) moves bytes at memory speed whatever baud rate its
// terminal settings name: cfsetospeed(B921600) on a pty only records the number. A real FCU's
// UART shifts one byte out in 10 bit times (start, 8 data, stop: 10.85 us at 921600 baud), one
// after the other, so a frame waits behind every byte queued before it. UartPort wraps the port
// and models both directions of the line:
//  - transmit (FCU -> companion): write() queues the bytes (never blocks the FCU's loop); byte i
//    is on the companion's side when its last bit has gone: done_i = max(written_i, done_{i-1})
//    + 10 / baud. A transmit buffer of kTxBuffer bytes; a write that does not fit is dropped
//    whole (false, as the other ports drop what the reader does not take) and counted;
//  - receive (companion -> FCU): a byte read from the port at time r reaches the firmware's
//    serial buffer at max(r, done_{i-1}) + 10 / baud (the companion's UART shifts it in).
// One thread moves the bytes: it reads the port, and hands the bytes to the other side when
// their time has come. It wakes when the kChunk-th queued byte (or the last one queued) is
// through, so a byte reaches the other side at most kChunk - 1 byte times late (33 us at
// 921600 baud) and the last byte of a burst on time. The loop reads the received side through
// fd() (a pipe): poll() on it as on the port.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <deque>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

#include <fcntl.h>
#include <poll.h>
#include <time.h>
#include <unistd.h>

#include "port.hpp"

namespace tern::fcu::emulator {

class UartPort final : public Port {
 public:
  static constexpr std::size_t kChunk = 4;        ///< bytes handed over at once (43 us at 921600 baud)
  static constexpr std::size_t kTxBuffer = 8192;  ///< bytes: the transmit buffer (89 ms at 921600 baud)

  struct Stats {
    std::uint64_t sent = 0, received = 0, dropped_writes = 0, dropped_bytes = 0;
    std::int64_t max_tx_queue_ns = 0;  ///< the longest a byte waited in the transmit buffer
  };

  /// inner: the port to pace (pseudo-terminal or socket); baud: bits per second, > 0.
  UartPort(std::unique_ptr<Port> inner, unsigned baud) : inner_(std::move(inner)), byte_ns_(byte_time(baud)) {
    if (pipe2(rx_pipe_, O_CLOEXEC | O_NONBLOCK) != 0 || pipe2(wake_, O_CLOEXEC | O_NONBLOCK) != 0)
      throw std::runtime_error(std::string("--baud: pipe failed: ") + std::strerror(errno));
    thread_ = std::thread([this] { run(); });
  }
  ~UartPort() override {
    stop_ = true;
    poke();
    thread_.join();
    for (int fd : {rx_pipe_[0], rx_pipe_[1], wake_[0], wake_[1]}) close(fd);
  }
  int fd() const override { return rx_pipe_[0]; }
  std::size_t read(std::uint8_t* buf, std::size_t n) override {
    const ssize_t r = ::read(rx_pipe_[0], buf, n);
    return r > 0 ? static_cast<std::size_t>(r) : 0;
  }
  bool write(const std::uint8_t* p, std::size_t n) override {
    {
      std::lock_guard lock(mu_);
      if (tx_.size() + n > kTxBuffer) {
        ++stats_.dropped_writes;
        stats_.dropped_bytes += n;
        return false;
      }
      const std::int64_t now = mono_ns();
      for (std::size_t i = 0; i < n; ++i) {
        tx_done_ = std::max(tx_done_, now) + byte_ns_;
        tx_.emplace_back(tx_done_, p[i]);
      }
      stats_.max_tx_queue_ns = std::max(stats_.max_tx_queue_ns, tx_done_ - now);
    }
    poke();
    return true;
  }
  Stats stats() const {
    std::lock_guard lock(mu_);
    return stats_;
  }
  std::int64_t byte_ns() const { return byte_ns_; }
  static std::int64_t mono_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
  }

 private:
  using Line = std::deque<std::pair<std::int64_t, std::uint8_t>>;  ///< (time the byte is through, byte)

  static std::int64_t byte_time(unsigned baud) {
    if (baud < 300 || baud > 12'000'000) throw std::runtime_error("--baud " + std::to_string(baud) + ": not a UART's rate (300..12000000)");
    return 10'000'000'000LL / baud;  // 8N1: 10 bit times a byte
  }

  void poke() {
    const std::uint8_t b = 1;
    [[maybe_unused]] const ssize_t w = ::write(wake_[1], &b, 1);
  }
  /// When the thread must next hand bytes over: the kChunk-th queued byte's time, or the last's.
  static std::int64_t due(const Line& q) { return q.empty() ? INT64_MAX : q[std::min(q.size(), kChunk) - 1].first; }
  /// Takes the bytes whose time has come, once a chunk is due.
  static std::string take(Line& q, std::int64_t now) {
    std::string out;
    if (due(q) > now) return out;
    while (!q.empty() && q.front().first <= now) {
      out.push_back(static_cast<char>(q.front().second));
      q.pop_front();
    }
    return out;
  }

  void run() {
    Line rx;
    std::int64_t rx_done = 0;
    std::uint8_t buf[4096];
    bool inner_open = true;
    while (!stop_) {
      std::int64_t next;
      {
        std::lock_guard lock(mu_);
        next = std::min(due(tx_), due(rx));
      }
      const std::int64_t wait = next == INT64_MAX ? 100'000'000 : std::max<std::int64_t>(0, next - mono_ns());
      pollfd p[2] = {{inner_open ? inner_->fd() : -1, POLLIN, 0}, {wake_[0], POLLIN, 0}};
      const timespec ts{static_cast<time_t>(wait / 1'000'000'000), static_cast<long>(wait % 1'000'000'000)};
      if (ppoll(p, 2, &ts, nullptr) > 0) {
        if (p[1].revents & POLLIN)
          while (::read(wake_[0], buf, sizeof buf) > 0) {
          }
        if (p[0].revents != 0) {
          const std::int64_t now = mono_ns();
          std::size_t got = 0;
          for (std::size_t n; (n = inner_->read(buf, sizeof buf)) > 0; got += n)
            for (std::size_t i = 0; i < n; ++i) {
              rx_done = std::max(rx_done, now) + byte_ns_;
              rx.emplace_back(rx_done, buf[i]);
            }
          if (got == 0 && (p[0].revents & (POLLHUP | POLLERR))) inner_open = false;  // the companion's end closed
        }
      }
      const std::int64_t now = mono_ns();
      const std::string in = take(rx, now);
      std::string out;
      {
        std::lock_guard lock(mu_);
        out = take(tx_, now);
        stats_.received += in.size();
        stats_.sent += out.size();
      }
      if (!in.empty()) write_all(rx_pipe_[1], reinterpret_cast<const std::uint8_t*>(in.data()), in.size());
      if (!out.empty()) inner_->write(reinterpret_cast<const std::uint8_t*>(out.data()), out.size());
    }
  }

  std::unique_ptr<Port> inner_;
  const std::int64_t byte_ns_;
  int rx_pipe_[2] = {-1, -1}, wake_[2] = {-1, -1};
  mutable std::mutex mu_;
  Line tx_;
  std::int64_t tx_done_ = 0;
  Stats stats_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace tern::fcu::emulator
