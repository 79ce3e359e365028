#include "console/console_server.hpp"

#include <chrono>
#include <deque>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <thread>
#include <utility>  // before Boost.Asio (its awaitable.hpp needs std::exchange)

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <fmt/format.h>

#include "config/error.hpp"

namespace tern::core {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;

namespace {

constexpr std::size_t kMaxRequest = 8 * 1024;     // bytes, header and body
constexpr std::size_t kMaxWsMessage = 64 * 1024;  // bytes
constexpr std::size_t kMaxQueued = 64;            // replies waiting for a slow page
constexpr auto kPollPeriod = std::chrono::milliseconds(40);
constexpr char kCookie[] = "tern_console";

std::string random_token() {
  std::random_device rd;
  std::string t;
  for (int i = 0; i < 4; ++i) t += fmt::format("{:08x}", rd());
  return t;
}

/// Equal strings, in a time that does not depend on where they differ.
bool same(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  unsigned char d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d |= static_cast<unsigned char>(a[i] ^ b[i]);
  return d == 0;
}

/// The value of `key` in a query string or cookie header ("a=1&b=2", "a=1; b=2").
std::string field(std::string_view text, std::string_view key, char sep) {
  while (!text.empty()) {
    while (!text.empty() && (text.front() == ' ' || text.front() == sep)) text.remove_prefix(1);
    const auto end = text.find(sep);
    const std::string_view item = text.substr(0, end);
    if (item.size() > key.size() && item.substr(0, key.size()) == key && item[key.size()] == '=')
      return std::string(item.substr(key.size() + 1));
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + 1);
  }
  return {};
}

std::string content_type(const std::filesystem::path& p) {
  const std::string e = p.extension().string();
  if (e == ".html") return "text/html; charset=utf-8";
  if (e == ".js") return "text/javascript; charset=utf-8";
  if (e == ".css") return "text/css; charset=utf-8";
  if (e == ".png") return "image/png";
  return "application/octet-stream";
}

struct File {
  std::string body, type;
};

}  // namespace

struct ConsoleServer::Impl {
  ConsoleApp& app;
  std::map<std::string, File> files;  // "/", "/console.js", ...
  std::string token = random_token();
  net::io_context ioc{1};
  tcp::acceptor acceptor{ioc};
  std::uint16_t port = 0;
  std::thread thread;

  explicit Impl(ConsoleApp& a) : app(a) {}
  void accept();
  bool host_ok(const Request& rq) const {
    const std::string host(rq[http::field::host]);
    return host == fmt::format("127.0.0.1:{}", port) || host == fmt::format("localhost:{}", port);
  }
  bool origin_ok(const Request& rq) const {
    const std::string origin(rq[http::field::origin]);
    return origin.empty() || origin == fmt::format("http://127.0.0.1:{}", port) || origin == fmt::format("http://localhost:{}", port);
  }
  /// The token from the URL's query, else from the cookie.
  bool authorised(const Request& rq) const {
    const std::string target(rq.target());
    const auto q = target.find('?');
    std::string given = q == std::string::npos ? "" : field(std::string_view(target).substr(q + 1), "token", '&');
    if (given.empty()) given = field(std::string(rq[http::field::cookie]), kCookie, ';');
    return host_ok(rq) && same(given, token);
  }
  Response respond(const Request& rq) const;
};

namespace {

Response plain(const Request& rq, http::status s, const std::string& text) {
  Response res{s, rq.version()};
  res.set(http::field::content_type, "text/plain; charset=utf-8");
  res.set(http::field::cache_control, "no-store");
  res.keep_alive(rq.keep_alive());
  res.body() = text + "\n";
  res.prepare_payload();
  return res;
}

}  // namespace

Response ConsoleServer::Impl::respond(const Request& rq) const {
  if (!authorised(rq)) return plain(rq, http::status::forbidden, "403 forbidden: open the URL with the token that tern printed");
  if (rq.method() != http::verb::get) return plain(rq, http::status::method_not_allowed, "405: GET only");
  std::string path(rq.target().substr(0, rq.target().find('?')));
  const auto f = files.find(path);
  if (f == files.end()) return plain(rq, http::status::not_found, "404 not found");
  Response res{http::status::ok, rq.version()};
  res.set(http::field::content_type, f->second.type);
  res.set(http::field::cache_control, "no-store");
  res.set("X-Content-Type-Options", "nosniff");
  res.set(
      "Content-Security-Policy",
      "default-src 'self'; style-src 'self' 'unsafe-inline'; connect-src 'self' ws://127.0.0.1:* ws://localhost:*; img-src 'self' data:");
  if (path == "/") res.set(http::field::set_cookie, fmt::format("{}={}; HttpOnly; SameSite=Strict; Path=/", kCookie, token));
  res.keep_alive(rq.keep_alive());
  res.body() = f->second.body;
  res.prepare_payload();
  return res;
}

namespace {

/// One page's WebSocket.
class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket&& s, ConsoleApp& app) : ws_(std::move(s)), timer_(ws_.get_executor()), app_(app) {}

  void run(Request rq) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kMaxWsMessage);
    ws_.async_accept(rq, [self = shared_from_this()](beast::error_code ec) {
      if (ec) return;
      self->open_ = true;
      self->send(self->app_.on_open());
      self->read();
      self->tick();
    });
  }

 private:
  void read() {
    ws_.async_read(in_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->close();
      const std::string text = beast::buffers_to_string(self->in_.data());
      self->in_.consume(self->in_.size());
      if (const std::string reply = self->app_.on_message(text); !reply.empty()) self->send(reply);
      self->read();
    });
  }
  void tick() {
    timer_.expires_after(kPollPeriod);
    timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
      if (ec || !self->open_) return;
      if (self->out_.empty())  // a page that has not read the last frame gets no new one yet
        if (auto m = self->app_.poll(self->cursor_)) self->send(std::move(*m));
      self->tick();
    });
  }
  void send(std::string m) {
    if (!open_) return;
    if (out_.size() >= kMaxQueued) return close();
    out_.push_back(std::move(m));
    if (out_.size() == 1) write();
  }
  void write() {
    ws_.text(true);
    ws_.async_write(net::buffer(out_.front()), [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->close();
      self->out_.pop_front();
      if (!self->out_.empty() && self->open_) self->write();
    });
  }
  void close() {
    if (!open_) return;
    open_ = false;
    timer_.cancel();
    beast::error_code ec;
    beast::get_lowest_layer(ws_).socket().close(ec);
    app_.on_close();
  }

  websocket::stream<beast::tcp_stream> ws_;
  net::steady_timer timer_;
  beast::flat_buffer in_;
  std::deque<std::string> out_;
  ConsoleApp& app_;
  std::uint64_t cursor_ = 0;
  bool open_ = false;
};

/// One HTTP connection: requests answered in turn; a WebSocket upgrade hands the socket over.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket&& s, const ConsoleServer::Impl& srv) : stream_(std::move(s)), srv_(srv) {}
  void read() {
    parser_.emplace();
    parser_->header_limit(kMaxRequest);
    parser_->body_limit(kMaxRequest);
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(stream_, buf_, *parser_, [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

 private:
  void on_read(beast::error_code ec) {
    if (ec) return shutdown();
    Request rq = parser_->release();
    if (websocket::is_upgrade(rq) && rq.target().substr(0, 3) == "/ws") {
      if (!srv_.authorised(rq) || !srv_.origin_ok(rq)) return write(plain(rq, http::status::forbidden, "403 forbidden"));
      stream_.expires_never();
      return std::make_shared<WsSession>(stream_.release_socket(), srv_.app)->run(std::move(rq));
    }
    write(srv_.respond(rq));
  }
  void write(Response res) {
    auto sp = std::make_shared<Response>(std::move(res));
    http::async_write(stream_, *sp, [self = shared_from_this(), sp](beast::error_code ec, std::size_t) {
      if (ec || sp->need_eof()) return self->shutdown();
      self->read();
    });
  }
  void shutdown() {
    beast::error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
  }

  beast::tcp_stream stream_;
  beast::flat_buffer buf_;
  std::optional<http::request_parser<http::string_body>> parser_;
  const ConsoleServer::Impl& srv_;
};

}  // namespace

void ConsoleServer::Impl::accept() {
  acceptor.async_accept(net::make_strand(ioc), [this](beast::error_code ec, tcp::socket s) {
    if (!ec) std::make_shared<HttpSession>(std::move(s), *this)->read();
    if (acceptor.is_open()) accept();
  });
}

ConsoleServer::ConsoleServer(const std::vector<std::filesystem::path>& files, ConsoleApp& app, std::uint16_t port)
    : impl_(std::make_unique<Impl>(app)) {
  for (std::size_t i = 0; i < files.size(); ++i) {
    std::ifstream in(files[i], std::ios::binary);
    std::ostringstream body;
    body << in.rdbuf();
    if (!in) throw ConfigError(fmt::format("console: cannot read {} (make deps, then rebuild)", files[i].string()));
    impl_->files[i == 0 ? "/" : "/" + files[i].filename().string()] = {body.str(), content_type(files[i])};
  }
  try {
    const tcp::endpoint at(net::ip::make_address("127.0.0.1"), port);
    impl_->acceptor.open(at.protocol());
    impl_->acceptor.set_option(net::socket_base::reuse_address(true));
    impl_->acceptor.bind(at);
    impl_->acceptor.listen();
    impl_->port = impl_->acceptor.local_endpoint().port();
  } catch (const boost::system::system_error& e) {
    throw ConfigError(fmt::format("console: cannot listen on 127.0.0.1:{}: {}", port, e.what()));
  }
  impl_->accept();
  impl_->thread = std::thread([this] { impl_->ioc.run(); });
}

ConsoleServer::~ConsoleServer() {
  impl_->ioc.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

std::uint16_t ConsoleServer::port() const { return impl_->port; }
const std::string& ConsoleServer::token() const { return impl_->token; }
std::string ConsoleServer::url() const { return fmt::format("http://127.0.0.1:{}/?token={}", impl_->port, impl_->token); }

}  // namespace tern::core
