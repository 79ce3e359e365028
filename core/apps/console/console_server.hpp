// core/apps/console/console_server.hpp: the console's web server: HTTP and WebSocket on loopback
// (Boost.Beast), with a secret token in the URL as Jupyter does.
//
// It binds 127.0.0.1 only, on `port` (0: a free port the system picks), and makes a random
// token (128 bits from std::random_device, hex). Every request must carry it: `?token=` in the
// URL, or the cookie the first page sets (HttpOnly, SameSite=Strict), so the page's own requests
// and its WebSocket need no token in their URLs. Refused with 403: a missing or wrong token, a
// Host header other than 127.0.0.1:PORT or localhost:PORT (DNS rebinding), a WebSocket whose
// Origin is another site. Only the files given at construction are served (read once into
// memory: no path ever reaches the file system), at "/" (the first) and "/NAME"; anything else
// is 404, any method but GET 405, a request over 8 KiB or a WebSocket message over 64 KiB closes
// the connection. A bad request never reaches the flight: the server runs on its own thread.
//
// The WebSocket at /ws talks to a ConsoleApp: on_open() is sent first, poll() every 40 ms (a
// new telemetry frame or nothing; skipped while the page has not read the previous frames),
// on_message() answers each text message from the page, on_close() when it goes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace tern::core {

class ConsoleApp {
 public:
  virtual ~ConsoleApp() = default;
  /// First message to a new page (JSON text).
  virtual std::string on_open() = 0;
  /// Called every 40 ms per page: the next message to push, if any. `cursor` is the page's own
  /// (0 at the start), for the app to tell what it already sent.
  virtual std::optional<std::string> poll(std::uint64_t& cursor) = 0;
  /// The reply to a message from the page ("" for none). Must not throw.
  virtual std::string on_message(const std::string& text) = 0;
  /// A page went away.
  virtual void on_close() = 0;
};

class ConsoleServer {
 public:
  /// Serves `files` (the first at "/") and `app` on 127.0.0.1:`port` (0: any free port) from a
  /// thread of its own. Throws ConfigError when a file cannot be read or the port not bound.
  ConsoleServer(const std::vector<std::filesystem::path>& files, ConsoleApp& app, std::uint16_t port = 0);
  ~ConsoleServer();  ///< stops serving and joins the thread
  ConsoleServer(const ConsoleServer&) = delete;
  ConsoleServer& operator=(const ConsoleServer&) = delete;

  std::uint16_t port() const;
  const std::string& token() const;
  /// http://127.0.0.1:PORT/?token=TOKEN
  std::string url() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace tern::core
