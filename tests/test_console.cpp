// The console's server (core/apps/console/console_server.hpp) and requests
// (console_commands.hpp): who gets in, what is served, what a page may ask of a host.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <thread>
#include <utility>  // before Boost.Asio (its awaitable.hpp needs std::exchange)

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "console/console_commands.hpp"
#include "console/console_server.hpp"
#include "console/telemetry.hpp"
#include "test_util.hpp"

using namespace tern;
using namespace tern::core;
namespace beast = boost::beast;
namespace http = beast::http;
namespace net = boost::asio;
using tcp = net::ip::tcp;

namespace {

/// Answers "echo: <text>", sends "tick" frames, counts closes.
class EchoApp final : public ConsoleApp {
 public:
  std::string on_open() override { return "hello"; }
  std::optional<std::string> poll(std::uint64_t& cursor) override {
    if (cursor >= 3) return std::nullopt;
    return "tick " + std::to_string(++cursor);
  }
  std::string on_message(const std::string& text) override { return "echo: " + text; }
  void on_close() override { ++closed; }
  std::atomic<int> closed{0};
};

struct Fixture {
  Fixture() {
    fs::create_directories(dir);
    std::ofstream(dir / "index.html") << "<html>page</html>";
    std::ofstream(dir / "app.js") << "let x = 1;";
  }
  fs::path dir = test_dir() / "console_server";
  EchoApp app;
  std::unique_ptr<ConsoleServer> server;
  void start() { server = std::make_unique<ConsoleServer>(std::vector<fs::path>{dir / "index.html", dir / "app.js"}, app); }
};

http::response<http::string_body> get(std::uint16_t port, const std::string& target, const std::string& host = "",
                                      const std::string& cookie = "", http::verb verb = http::verb::get) {
  net::io_context ioc;
  beast::tcp_stream s(ioc);
  s.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
  http::request<http::string_body> rq{verb, target, 11};
  rq.set(http::field::host, host.empty() ? "127.0.0.1:" + std::to_string(port) : host);
  if (!cookie.empty()) rq.set(http::field::cookie, cookie);
  http::write(s, rq);
  beast::flat_buffer b;
  http::response<http::string_body> res;
  http::read(s, b, res);
  return res;
}

}  // namespace

TEST_CASE("console server: only requests with the token get in; only the given files are served") {
  Fixture f;
  f.start();
  const auto port = f.server->port();
  const std::string tok = f.server->token();
  CHECK(tok.size() == 32);
  CHECK(f.server->url() == "http://127.0.0.1:" + std::to_string(port) + "/?token=" + tok);

  const auto page = get(port, "/?token=" + tok);
  CHECK(page.result() == http::status::ok);
  CHECK(page.body() == "<html>page</html>");
  CHECK(std::string(page[http::field::set_cookie]).find("tern_console=" + tok) != std::string::npos);
  CHECK(get(port, "/app.js", "", "tern_console=" + tok).result() == http::status::ok);  // the page's own requests: the cookie

  CHECK(get(port, "/").result() == http::status::forbidden);
  CHECK(get(port, "/app.js").result() == http::status::forbidden);
  CHECK(get(port, "/?token=" + std::string(32, '0')).result() == http::status::forbidden);
  CHECK(get(port, "/?token=" + tok.substr(1)).result() == http::status::forbidden);
  CHECK(get(port, "/?token=" + tok, "evil.example:" + std::to_string(port)).result() == http::status::forbidden);
  CHECK(get(port, "/app.js", "", "tern_console=wrong").result() == http::status::forbidden);
  CHECK(get(port, "/../index.html?token=" + tok).result() == http::status::not_found);
  CHECK(get(port, "/etc/passwd?token=" + tok).result() == http::status::not_found);
  CHECK(get(port, "/?token=" + tok, "", "", http::verb::post).result() == http::status::method_not_allowed);
}

TEST_CASE("console server: a request over 8 KiB is dropped, and the server still serves") {
  Fixture f;
  f.start();
  const auto port = f.server->port();
  net::io_context ioc;
  beast::tcp_stream s(ioc);
  s.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
  http::request<http::string_body> rq{http::verb::get, "/?token=" + f.server->token(), 11};
  rq.set(http::field::host, "127.0.0.1:" + std::to_string(port));
  rq.set("X-Junk", std::string(20000, 'x'));
  beast::error_code ec;
  http::write(s, rq, ec);
  beast::flat_buffer b;
  http::response<http::string_body> res;
  http::read(s, b, res, ec);
  CHECK(ec);  // closed without an answer
  CHECK(get(port, "/?token=" + f.server->token()).result() == http::status::ok);
}

TEST_CASE("console server: the WebSocket needs the token and a same-site origin; it carries the app's messages") {
  Fixture f;
  f.start();
  const auto port = f.server->port();
  const std::string host = "127.0.0.1:" + std::to_string(port);
  const auto open_ws = [&](const std::string& target, const std::string& origin, beast::websocket::stream<beast::tcp_stream>& ws) {
    beast::get_lowest_layer(ws).connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
    ws.set_option(beast::websocket::stream_base::decorator([origin](beast::websocket::request_type& rq) {
      if (!origin.empty()) rq.set(http::field::origin, origin);
    }));
    beast::error_code ec;
    ws.handshake(host, target, ec);
    return ec;
  };
  net::io_context ioc;
  {
    beast::websocket::stream<beast::tcp_stream> ws(ioc);
    CHECK(open_ws("/ws", "", ws));  // no token: refused
  }
  {
    beast::websocket::stream<beast::tcp_stream> ws(ioc);
    CHECK(open_ws("/ws?token=" + f.server->token(), "http://evil.example", ws));  // another site's page
  }
  beast::websocket::stream<beast::tcp_stream> ws(ioc);
  REQUIRE_FALSE(open_ws("/ws?token=" + f.server->token(), "http://" + host, ws));
  beast::flat_buffer b;
  const auto next = [&] {
    b.consume(b.size());
    ws.read(b);
    return beast::buffers_to_string(b.data());
  };
  CHECK(next() == "hello");
  ws.write(net::buffer(std::string("{\"type\":\"param\"}")));
  std::vector<std::string> got;
  for (int i = 0; i < 4; ++i) got.push_back(next());
  CHECK(std::count(got.begin(), got.end(), "echo: {\"type\":\"param\"}") == 1);
  CHECK(std::count(got.begin(), got.end(), "tick 1") == 1);
  ws.close(beast::websocket::close_code::normal);
  for (int i = 0; i < 100 && f.app.closed == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  CHECK(f.app.closed == 1);
}

TEST_CASE("console requests: sticks in range or refused; malformed requests answered with an error") {
  const auto rc = pilot_from_json(nlohmann::json::parse(R"({"manual":true,"angle":true,"roll":0.5,"pitch":-1,"yaw":0,"throttle":1})"));
  CHECK(rc.rc_override);
  CHECK(rc.roll == 0.5);
  CHECK(rc.pitch == -1.0);
  CHECK(rc.throttle == 1.0);
  CHECK(rc.aux[0] == 1.0);
  CHECK_FALSE(rc.failsafe);
  CHECK_THROWS_WITH(pilot_from_json(nlohmann::json::parse(R"({"roll":1.5,"pitch":0,"yaw":0,"throttle":0})")),
                    doctest::Contains("'roll' out of range"));
  CHECK_THROWS_WITH(pilot_from_json(nlohmann::json::parse(R"({"roll":0,"pitch":0,"yaw":0,"throttle":-0.1})")),
                    doctest::Contains("'throttle' out of range"));
  CHECK_THROWS_WITH(pilot_from_json(nlohmann::json::parse(R"({"roll":0,"pitch":"up","yaw":0,"throttle":0})")),
                    doctest::Contains("'pitch' must be a number"));
  CHECK_THROWS(pilot_from_json(nlohmann::json::parse(R"({"roll":0,"yaw":0,"throttle":0})")));
}

TEST_CASE("console telemetry: non-finite values go to the page as null, altitude as h = -p_d") {
  Snapshot s;
  s.t = 1'500'000'000;
  s.has_state = true;
  s.state.p_d = -120.0;
  s.state.phi = std::nan("");
  s.state.w_n = 3.0;
  s.state.w_e = -4.0;
  const auto j = to_json(s, true);
  CHECK(j["t"] == 1.5);
  CHECK(j["state"]["h"] == 120.0);
  CHECK(j["state"]["p_d"] == -120.0);  // the 3-D view's NED
  CHECK(j["state"]["w"] == nlohmann::json::array({3.0, -4.0, 0.0}));
  CHECK(j["state"]["phi"].is_null());
  CHECK_FALSE(j.contains("actuators"));
  CHECK(j.dump().find("nan") == std::string::npos);
}

TEST_CASE("console telemetry: a multi-vehicle flight's other vehicles as traffic, none without") {
  Snapshot s;
  CHECK_FALSE(to_json(s, false).contains("traffic"));
  s.traffic.push_back({"uav2", 100.0, -50.0, 90.0, 1.0});
  s.traffic.push_back({"uav3", std::nan(""), 0.0, 80.0, 0.0});
  const auto j = to_json(s, false);
  REQUIRE(j["traffic"].size() == 2);
  CHECK(j["traffic"][0]["name"] == "uav2");
  CHECK(j["traffic"][0]["p_e"] == -50.0);
  CHECK(j["traffic"][0]["h"] == 90.0);
  CHECK(j["traffic"][1]["p_n"].is_null());
}

TEST_CASE("console requests on a host: parameters go the way of `tern param set` into params.csv; bad ones are answered, not thrown") {
  HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / "console_requests";
  Host h(load_config(write_file("console.yaml", base_config())), o);
  h.build();
  const auto answer = [&h](const std::string& rq) { return nlohmann::json::parse(handle_request(h, rq)); };
  CHECK(answer("{not json")["type"] == "error");
  CHECK(answer("[1, 2]")["type"] == "error");
  CHECK(answer(R"({"type":"launch"})")["message"] == "unknown request type 'launch' (param, pilot)");
  CHECK(answer(R"({"type":"param","name":"ctl.kq","value":0.1})")["message"].get<std::string>().find("unknown parameter 'ctl.kq'") == 0);
  CHECK(answer(R"({"type":"param","name":"ctl.kp","value":99})")["type"] == "error");  // out of range
  CHECK(answer(R"({"type":"param","name":"ctl.kp","value":{"a":1}})")["type"] == "error");
  CHECK(answer(R"({"type":"pilot","roll":0,"pitch":0,"yaw":0,"throttle":0})")["message"].get<std::string>().find(
            "no plugin instance reads topic 'pilot'") != std::string::npos);
  const auto ok = answer(R"({"type":"param","name":"ctl.tag","value":0.3})");
  CHECK(ok["type"] == "param_ok");
  CHECK(ok["value"] == 0.3);

  const auto cat = param_catalogue(h);
  const auto kp = std::find_if(cat.begin(), cat.end(), [](const auto& p) { return p["name"] == "ctl.kp"; });
  REQUIRE(kp != cat.end());
  CHECK((*kp)["instance"] == "ctl");
  CHECK((*kp)["kind"] == "number");
  CHECK((*kp)["live"] == true);
  CHECK((*kp)["max"].is_number());

  const FlightResult r = h.fly();
  REQUIRE(r.ok);
  const auto params = lines(read_file(r.run_dir / "params.csv"));
  CHECK(std::find(params.begin(), params.end(), "0.000000000,ctl.tag,0.3,console") != params.end());
}
