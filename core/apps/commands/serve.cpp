#include "commands/serve.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstring>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "config/cli_overrides.hpp"
#include "config/error.hpp"
#include "flight/host.hpp"

namespace tern::core {

namespace {

sockaddr_un address(const std::filesystem::path& p) {
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  if (p.string().size() >= sizeof(a.sun_path)) throw ConfigError("socket path too long: " + p.string());
  std::strncpy(a.sun_path, p.c_str(), sizeof(a.sun_path) - 1);
  return a;
}

void write_all(int fd, const std::string& s) {
  std::size_t off = 0;
  while (off < s.size()) {
    const ssize_t n = ::send(fd, s.data() + off, s.size() - off, MSG_NOSIGNAL);
    if (n <= 0) return;
    off += static_cast<std::size_t>(n);
  }
}

std::string read_line(int fd) {
  std::string line;
  char c;
  while (line.size() < 4096 && ::recv(fd, &c, 1, 0) == 1 && c != '\n') line.push_back(c);
  return line;
}

std::vector<std::string> words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> w;
  for (std::string x; in >> x;) w.push_back(x);
  return w;
}

struct Server {
  Host& host;
  std::string console_url;
  std::mutex flight_mu;  // one flight at a time
  std::atomic<bool> quit{false};

  std::string handle(const std::string& line) {
    const auto w = words(line);
    if (w.empty()) return "error: empty command (fly, abort, status, swap, phases, console, quit)";
    const std::string& cmd = w[0];
    try {
      if (cmd == "status") {
        return host.flying() ? fmt::format("ok: flying (flight {})", host.flights())
                             : fmt::format("ok: idle, {} flight(s) flown", host.flights());
      }
      if (cmd == "console") {
        if (console_url.empty()) return "error: this server has no console (start it with --realtime --console)";
        return "ok: " + console_url;
      }
      if (cmd == "quit") {
        quit = true;
        if (host.flying()) request_stop(SIGINT);
        return "ok: server stopping";
      }
      if (cmd == "fly") {
        std::unique_lock lk(flight_mu, std::try_to_lock);
        if (!lk.owns_lock() || host.flying()) return "error: a flight is in progress";
        std::optional<double> duration;
        if (w.size() > 1) {
          try {
            duration = std::stod(w[1]);
          } catch (const std::exception&) {
            return "error: fly: duration '" + w[1] + "' is not a number of seconds";
          }
          if (const std::string p = duration_problem(*duration); !p.empty()) return "error: fly: duration " + p;
        }
        host.set_duration(duration);
        const FlightResult r = host.fly();
        // first line: the outcome; then the summary tables `tern fly` prints
        return fmt::format("{}: flight {} ended ({}) at t={:.3f} s; log: {}{}\n{}", r.ok ? "ok" : "error", host.flights(), r.end_reason,
                           to_seconds(r.flown), r.run_dir.string(), r.log_error.empty() ? "" : " (incomplete: " + r.log_error + ")",
                           r.summary);
      }
      if (cmd == "abort") {
        if (!host.abort_flight()) return "error: abort: no flight in progress";
        return fmt::format("ok: flight {} aborting (its log ends with the current tick; the server stays)", host.flights());
      }
      if (cmd == "swap") {
        if (w.size() != 3) return "error: usage: swap INSTANCE PATH";
        if (host.flying()) return "error: swap refused: a flight is in progress; swap between flights";
        std::unique_lock lk(flight_mu, std::try_to_lock);
        if (!lk.owns_lock()) return "error: swap refused: a flight is in progress; swap between flights";
        const SwapReport rep = host.swap(w[1], w[2]);
        if (rep.same())
          return fmt::format("ok: {} now runs {}\nwarning: same library (sha256 {}): did the build fail?", w[1], w[2], rep.new_sha256);
        return fmt::format("ok: {} now runs {} (sha256 {} -> {})", w[1], w[2], rep.old_sha256.substr(0, 12), rep.new_sha256.substr(0, 12));
      }
      if (cmd == "phases") {
        if (host.flying()) return "error: phases refused: a flight is in progress; change the table between flights";
        std::unique_lock lk(flight_mu, std::try_to_lock);
        if (!lk.owns_lock()) return "error: phases refused: a flight is in progress; change the table between flights";
        std::vector<std::string> items;
        std::optional<std::string> fallback;
        for (std::size_t i = 1; i < w.size(); ++i) {
          if (w[i].rfind("fallback=", 0) == 0)
            fallback = w[i].substr(std::string("fallback=").size());
          else
            items.push_back(w[i]);
        }
        // a partial table: the phases named change, the others keep their controller
        std::map<msg::Phase, std::string> table = host.config().phases;
        for (const auto& [phase, instance] : parse_phase_entries(host.config(), items, "phases")) table[phase] = instance;
        host.set_phases(table, fallback);
        return "ok: phase table changed";
      }
      return "error: unknown command '" + cmd + "' (fly, abort, status, swap, phases, console, quit)";
    } catch (const std::exception& e) {
      return std::string("error: ") + e.what();
    }
  }
};

}  // namespace

std::filesystem::path default_socket() {
  if (const char* env = std::getenv("TERN_SOCKET")) return env;
  return fmt::format("/tmp/tern-serve-{}.sock", ::getuid());
}

int serve(Host& host, const std::filesystem::path& socket_path, const std::string& console_url) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  if (fd < 0) throw ConfigError(std::string("serve: cannot create a socket: ") + std::strerror(errno));
  const sockaddr_un a = address(socket_path);
  if (std::filesystem::exists(socket_path)) {
    // a live server answers; a stale socket file is replaced
    bool live = false;
    try {
      live = !send_command(socket_path, "status").empty();
    } catch (const ConfigError&) {
    }
    if (live) {
      ::close(fd);
      throw ConfigError("serve: another tern serve is listening on " + socket_path.string() + " (use --socket)");
    }
    std::filesystem::remove(socket_path);
  }
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0 || ::listen(fd, 8) != 0) {
    const std::string err = std::strerror(errno);
    ::close(fd);
    throw ConfigError("serve: cannot listen on " + socket_path.string() + ": " + err);
  }
  if (!console_url.empty()) ::chmod(socket_path.c_str(), 0600);  // the console's token is handed out here: this user only
  install_signal_handlers();
  host.logger()->info("serving '{}' on {} (commands: fly [s], abort, status, swap INSTANCE PATH, phases ..., quit)", host.config().name,
                      socket_path.string());
  Server server{host, console_url, {}, {}};
  std::vector<std::thread> clients;
  while (!server.quit && stop_signal() == 0) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 200) <= 0) continue;
    const int c = ::accept(fd, nullptr, nullptr);
    if (c < 0) continue;
    clients.emplace_back([&server, c] {
      const std::string line = read_line(c);
      write_all(c, server.handle(line) + "\n");
      ::close(c);
    });
  }
  if (host.flying()) request_stop(SIGINT);
  for (auto& t : clients) t.join();
  ::close(fd);
  std::filesystem::remove(socket_path);
  host.logger()->info("server stopped");
  return 0;
}

namespace {

/// A socket connected to the server at `socket_path`, retried every 50 ms for `wait_s` seconds
/// while nobody listens there yet (no socket file, or no listener on it: a server that is
/// starting). Throws ConfigError naming the path, the last error and the wait.
int connect_to_server(const std::filesystem::path& socket_path, double wait_s) {
  const sockaddr_un a = address(socket_path);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(std::max(0.0, wait_s));
  for (;;) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    if (fd < 0) throw ConfigError(std::string("cannot create a socket: ") + std::strerror(errno));
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0) return fd;
    const int err = errno;
    ::close(fd);
    const bool starting = err == ENOENT || err == ECONNREFUSED;
    if (!starting || std::chrono::steady_clock::now() >= deadline) {
      const std::string waited = wait_s > 0 ? fmt::format(" after waiting {:g} s", wait_s) : std::string();
      throw ConfigError("no tern serve is listening at " + socket_path.string() + waited + " (" + std::strerror(err) +
                        "): start one with `tern serve CONFIG`, or name its socket with --socket");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

}  // namespace

std::string send_command(const std::filesystem::path& socket_path, const std::string& line, double wait_s) {
  const int fd = connect_to_server(socket_path, wait_s);
  write_all(fd, line + "\n");
  std::string reply;
  char buf[512];
  for (ssize_t n; (n = ::recv(fd, buf, sizeof buf, 0)) > 0;) reply.append(buf, static_cast<std::size_t>(n));
  ::close(fd);
  while (!reply.empty() && reply.back() == '\n') reply.pop_back();
  return reply;
}

}  // namespace tern::core
