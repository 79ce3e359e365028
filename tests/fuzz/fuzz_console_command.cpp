// fuzz_console_command: libFuzzer target for the flight console's requests
// (core/apps/console/console_commands.hpp handle_request), as the console's server hands it each
// WebSocket message from the page, without a server: one host, built once from the test plugins
// (tests/plugins: test_sensor, test_filter, test_controller; nothing flies), takes every input.
// Any bytes: an answer that is one JSON object, {"type":"param_ok",...} for a parameter the host
// took or {"type":"error","message":...}; never a crash, an exception out of handle_request, or
// an answer that is not JSON. The sticks of a "pilot" request (pilot_from_json) are read too: in
// their ranges, or std::invalid_argument naming the field. The host's directory (its config, a
// log directory it never writes to since nothing flies) is under TMPDIR.
#include <cmath>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "config/config.hpp"
#include "console/console_commands.hpp"
#include "flight/host.hpp"
#include "fuzz_host.hpp"

using namespace tern::core;

namespace {

Host& host() {
  static const std::unique_ptr<Host> h = tern::fuzz::test_plugin_host("console_fuzz").host;
  return *h;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string answer = handle_request(host(), text);
  // every request is answered here (a pilot request too: no test plugin reads `pilot`)
  const nlohmann::json a = nlohmann::json::parse(answer);  // throws (a finding) if the answer is not JSON
  if (!a.is_object() || !a.contains("type")) __builtin_trap();
  const std::string type = a["type"].get<std::string>();
  if (type == "error") {
    if (!a["message"].is_string()) __builtin_trap();
  } else if (type == "param_ok") {
    if (!a["name"].is_string() || !a.contains("value")) __builtin_trap();
  } else {
    __builtin_trap();
  }
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_discarded() && j.is_object()) {
    try {
      const auto rc = pilot_from_json(j);
      if (!(std::abs(rc.roll) <= 1 && std::abs(rc.pitch) <= 1 && std::abs(rc.yaw) <= 1 && rc.throttle >= 0 && rc.throttle <= 1))
        __builtin_trap();
    } catch (const std::invalid_argument& e) {
      tern::fuzz::note(e);
    } catch (const nlohmann::json::exception& e) {  // "manual" or "angle" not a boolean
      tern::fuzz::note(e);
    }
  }
  return 0;
}
