// core/apps/commands/control_commands.cpp: the commands that drive a running `tern serve` over its
// control socket (serve.hpp): swap, phases, console and remote. Each sends one line and prints
// the reply; the exit status is 0 when the reply starts with "ok".
#include <cstdio>
#include <memory>

#include "commands/commands.hpp"
#include "commands/serve.hpp"

namespace tern::core {

namespace {

/// The server's socket and how long to wait for a server that is starting, as every client
/// command takes them.
struct ServerAddress {
  std::string socket = default_socket().string();
  double wait_s = kServerWaitS;
};

/// Sends `line`, prints the reply: 0 for "ok...", else 1.
int send_line(const ServerAddress& server, const std::string& line) {
  const std::string reply = send_command(server.socket, line, server.wait_s);
  std::puts(reply.c_str());
  return reply.rfind("ok", 0) == 0 ? 0 : 1;
}

void add_server_options(CLI::App* c, ServerAddress& server) {
  c->add_option("--socket", server.socket, "control socket of the server")->capture_default_str();
  c->add_option("--wait", server.wait_s, "seconds to wait for a server that is still starting")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
}

Command add_swap(CLI::App& app) {
  struct Options {
    std::string instance, so_path;
    ServerAddress server;
  };
  auto o = std::make_shared<Options>();
  auto* c = app.add_subcommand("swap", "between flights of `tern serve`: replace an instance's plugin with another .so");
  c->add_option("instance", o->instance, "instance name in the mission config")->required();
  c->add_option("path", o->so_path, "the new plugin: a path to a .so, or a plugin name")->required();
  add_server_options(c, o->server);
  return {c, [o] {
            std::string p = o->so_path;
            if (p.find('/') != std::string::npos) p = fs::absolute(p).string();
            return send_line(o->server, "swap " + o->instance + " " + p);
          }};
}

Command add_phases(CLI::App& app) {
  struct Options {
    std::vector<std::string> table;
    std::string fallback;
    ServerAddress server;
  };
  auto o = std::make_shared<Options>();
  auto* c = app.add_subcommand("phases", "between flights of `tern serve`: set the phase -> controller table");
  c->add_option("table", o->table, "PHASE=INSTANCE ... (the phases named change; the others keep their controller)")->required();
  c->add_option("--fallback", o->fallback, "controller used if the active one fails");
  add_server_options(c, o->server);
  return {c, [o] {
            std::string line = "phases";
            for (const auto& a : o->table) line += " " + a;
            if (!o->fallback.empty()) line += " fallback=" + o->fallback;
            return send_line(o->server, line);
          }};
}

Command add_console_url(CLI::App& app) {
  auto server = std::make_shared<ServerAddress>();
  auto* c = app.add_subcommand("console", "the URL of the console of a `tern serve --realtime --console` (open it in a browser)");
  add_server_options(c, *server);
  return {c, [server] {
            const std::string reply = send_command(server->socket, "console", server->wait_s);
            if (reply.rfind("ok: ", 0) != 0) return fail(reply);
            std::printf("console: %s\n", reply.substr(4).c_str());
            return 0;
          }};
}

Command add_remote(CLI::App& app) {
  struct Options {
    std::string command;
    std::vector<std::string> args;
    ServerAddress server;
  };
  auto o = std::make_shared<Options>();
  auto* c = app.add_subcommand(
      "remote",
      "send a command to `tern serve`: fly [SECONDS] (prints the summary tables), abort (ends the flight, keeps the server), status, quit");
  c->add_option("command", o->command, "fly, abort, status or quit")->required()->check(CLI::IsMember({"fly", "abort", "status", "quit"}));
  c->add_option("args", o->args, "fly: flight length in seconds");
  add_server_options(c, o->server);
  return {c, [o] {
            std::string line = o->command;
            for (const auto& a : o->args) line += " " + a;
            return send_line(o->server, line);
          }};
}

}  // namespace

std::vector<Command> add_control_commands(CLI::App& app) { return {add_swap(app), add_phases(app), add_console_url(app), add_remote(app)}; }

}  // namespace tern::core
