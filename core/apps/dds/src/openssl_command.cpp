// core/apps/dds/src/openssl_command.cpp: fork + exec of `openssl`, stderr kept for the error message.
#include "openssl_command.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "dds_bridge.hpp"

namespace tern::core::ddsi {

namespace fs = std::filesystem;

fs::path find_openssl() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path != nullptr ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const fs::path p = fs::path(dir.empty() ? "." : dir) / "openssl";
    if (access(p.c_str(), X_OK) == 0) return p;
  }
  return {};
}

namespace {
/// The last non-empty line of `file`.
std::string last_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}
}  // namespace

void require_openssl() {
  if (find_openssl().empty()) throw DdsError("openssl not found: install Debian's openssl package (apt-get install openssl)");
}

void run_openssl(const std::vector<std::string>& args, const fs::path& cwd) {
  require_openssl();
  const fs::path prog = find_openssl();
  const fs::path err = cwd / ".openssl.err";
  const pid_t pid = fork();
  if (pid < 0) throw DdsError("cannot run openssl: fork failed");
  if (pid == 0) {
    std::vector<char*> argv{const_cast<char*>("openssl")};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const int null = open("/dev/null", O_RDWR);
    const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (null < 0 || e < 0 || chdir(cwd.c_str()) != 0) _exit(126);
    dup2(null, 0);
    dup2(null, 1);
    dup2(e, 2);
    execv(prog.c_str(), argv.data());
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  const std::string why = last_line(err);
  std::error_code ec;
  fs::remove(err, ec);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw DdsError("openssl " + args.front() + " failed" + (why.empty() ? "" : ": " + why));
}

}  // namespace tern::core::ddsi
