// core/apps/commands/serve.hpp: `tern serve`: one host kept alive across flights, driven over a local
// control channel (a Unix-domain socket, one text command per connection, reply lines back).
//
// Commands: `fly [SECONDS]`, `status`, `swap INSTANCE PATH`,
// `phases PHASE=INSTANCE... [fallback=INSTANCE]`, `console` (the console's URL, `tern console`),
// `quit`. Replies start with "ok:" or "error:".
// `phases` changes the phases it names (read as --phases reads them, cli_overrides.hpp); the
// others keep their controller. `swap` and `phases` are refused while a flight is in progress.
#pragma once

#include <filesystem>
#include <string>

namespace tern::core {

class Host;

/// $TERN_SOCKET, else /tmp/tern-serve-<uid>.sock.
std::filesystem::path default_socket();

/// Serves `host` on `socket` until `quit` or SIGINT/SIGTERM. Returns the exit status.
/// `console_url`: the URL (with its token) of the console serving `host`, "" if none; the
/// `console` command hands it to a client of the socket (only this user can open it).
int serve(Host& host, const std::filesystem::path& socket, const std::string& console_url = "");

/// How long a client command (`tern remote`, `swap`, `phases`, `console`) waits by default for a
/// server that is still starting (`tern serve CONFIG &` then `tern remote fly` at once), in s.
constexpr double kServerWaitS = 10.0;

/// Sends one command line to a server and returns its reply. While nobody listens at `socket`
/// yet, retries for up to `wait_s` seconds (0: one try). Throws ConfigError when no server
/// answers in that time.
std::string send_command(const std::filesystem::path& socket, const std::string& line, double wait_s = 0.0);

}  // namespace tern::core
