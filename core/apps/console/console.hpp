// core/apps/console/console.hpp: `tern fly --realtime --console` and `tern serve --console`: the
// flight console, a web page on loopback that shows a flight live and flies it (docs/tuning.md).
//
// Console ties a Host to a ConsoleServer (console_server.hpp): its TelemetryTap
// (telemetry.hpp) becomes the host's tick observer, so construct it between flights and after
// anything else that sets one; requests from the page go to handle_request
// (console_commands.hpp). The page (core/apps/console/index.html, console.js, console.css, with uPlot
// from npm, copied into <prefix>/share/tern/console by the build) is read once, at construction.
// When the last page closes, the sticks are released: override off, centred (a lost link must
// not leave the aircraft in manual with a stick held over).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "console/console_server.hpp"
#include "console/telemetry.hpp"

namespace tern::core {

class Host;

/// The directory holding the console's files: $TERN_CONSOLE_DIR, else share/tern/console next to
/// the tern binary (build tree and installation alike). Throws ConfigError naming what is missing.
std::filesystem::path console_asset_dir();

class Console final : public ConsoleApp {
 public:
  /// Serves a console for `host` on 127.0.0.1:`port` (0: a free one). Throws ConfigError.
  Console(Host& host, const std::filesystem::path& assets, std::uint16_t port = 0);
  ~Console() override;  ///< removes the tick observer

  std::string url() const { return server_->url(); }
  /// A multi-vehicle flight's other vehicles, drawn on the page's track (TelemetryTap::set_traffic).
  void set_traffic(std::function<std::vector<Traffic>()> source) { tap_.set_traffic(std::move(source)); }

  std::string on_open() override;
  std::optional<std::string> poll(std::uint64_t& cursor) override;
  std::string on_message(const std::string& text) override;
  void on_close() override;

 private:
  Host& host_;
  TelemetryTap tap_;
  int observer_id_ = 0;   ///< the host's tick observer feeding tap_
  nlohmann::json hello_;  // built before serving; then the server thread only
  int pages_ = 0;         // server thread only
  std::unique_ptr<ConsoleServer> server_;
};

}  // namespace tern::core
