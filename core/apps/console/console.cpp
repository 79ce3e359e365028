#include "console/console.hpp"

#include <cstdlib>

#include "console/console_commands.hpp"
#include "config/error.hpp"
#include "flight/host.hpp"
#include "tern/aircraft.hpp"

namespace tern::core {
namespace {

constexpr Nanos kTelemetryPeriod = 40'000'000;  // ns of flight time: 25 Hz to the page
const char* const kFiles[] = {"index.html", "console.js", "console.css", "uPlot.iife.min.js", "uPlot.min.css", "view3d.js"};

/// The 3-D view's aircraft size (view3d.js): span b, chord c, and the gear structure's nose and
/// tail hard points (m ahead of / behind the CG); null without an aircraft file, {"error": why}
/// when it does not load (the view says so on the page).
nlohmann::json aircraft_dims(const Host& host) {
  if (host.config().aircraft.empty()) return nullptr;
  try {
    const Aircraft ac = load_aircraft(host.config().aircraft.string());
    nlohmann::json d = {{"b", ac.b}, {"c", ac.c}, {"nose", 0.0}, {"tail", 0.0}};
    for (const auto& [name, p] : ac.gear.structure) {
      if (name == "nose") d["nose"] = p.x();
      if (name == "tail") d["tail"] = -p.x();
    }
    return d;
  } catch (const std::exception& e) {
    return {{"error", e.what()}};
  }
}

}  // namespace

std::filesystem::path console_asset_dir() {
  std::filesystem::path dir;
  if (const char* env = std::getenv("TERN_CONSOLE_DIR"); env != nullptr && *env != '\0') {
    dir = env;
  } else {
    std::error_code ec;
    dir = (std::filesystem::read_symlink("/proc/self/exe", ec).parent_path() / ".." / "share" / "tern" / "console").lexically_normal();
  }
  for (const char* f : kFiles)
    if (!std::filesystem::exists(dir / f))
      throw ConfigError("console: " + (dir / f).string() + " is missing (uPlot and three.js come from npm: run `make deps`, then rebuild)");
  return dir;
}

Console::Console(Host& host, const std::filesystem::path& assets, std::uint16_t port) : host_(host), tap_(kTelemetryPeriod) {
  hello_ = {{"type", "hello"},
            {"mission", host.config().name},
            {"params", param_catalogue(host)},
            {"pilot", host.takes_pilot()},
            {"telemetry_hz", 1e9 / static_cast<double>(kTelemetryPeriod)},
            {"aircraft", aircraft_dims(host)}};
  for (const auto& inst : host.instances()) hello_["instances"].push_back({{"name", inst->cfg.name}, {"plugin", inst->info.name}});
  std::vector<std::filesystem::path> files;
  for (const char* f : kFiles) files.push_back(assets / f);
  server_ = std::make_unique<ConsoleServer>(files, *this, port);
  observer_id_ = host_.add_tick_observer(tap_.observer(host_));
}

Console::~Console() {
  server_.reset();  // no page calls in any more
  host_.remove_tick_observer(observer_id_);
}

std::string Console::on_open() {
  ++pages_;
  return hello_.dump();
}

std::optional<std::string> Console::poll(std::uint64_t& cursor) {
  const Snapshot s = tap_.latest();
  if (s.seq == 0 || s.seq == cursor) return std::nullopt;
  cursor = s.seq;
  return to_json(s, true).dump();
}

std::string Console::on_message(const std::string& text) {
  std::string reply = handle_request(host_, text);
  // a page opened later shows the value this one set
  if (const auto r = nlohmann::json::parse(reply, nullptr, false); r.is_object() && r.value("type", "") == "param_ok")
    for (auto& p : hello_["params"])
      if (p["name"] == r["name"]) p["value"] = r["value"];
  return reply;
}

void Console::on_close() {
  if (--pages_ > 0 || !host_.takes_pilot()) return;
  host_.set_pilot(msg::Rc{});  // centred, override off
}

}  // namespace tern::core
