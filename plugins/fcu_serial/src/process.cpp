// process.cpp: see tern_fcu_serial/process.hpp.
#include "tern_fcu_serial/process.hpp"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <thread>

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace tern::fcu {

namespace {
std::int64_t mono_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& argv, int pass_fd) {
  if (argv.empty()) throw std::runtime_error("ChildProcess: empty command");
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("cannot create a pipe for " + argv[0] + ": " + std::strerror(errno));
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, fds[1], STDOUT_FILENO);
  if (pass_fd >= 0) posix_spawn_file_actions_adddup2(&fa, pass_fd, kPassedFd);  // dup2 clears close-on-exec
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0].c_str(), &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  close(fds[1]);
  if (rc != 0) {
    close(fds[0]);
    throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(rc));
  }
  pid_ = pid;
  out_fd_ = fds[0];
}

ChildProcess::~ChildProcess() { stop(); }

std::string ChildProcess::read_line(std::int64_t timeout_ns) {
  const std::int64_t deadline = mono_ns() + timeout_ns;
  for (;;) {
    const auto nl = pending_.find('\n');
    if (nl != std::string::npos) {
      std::string line = pending_.substr(0, nl);
      pending_.erase(0, nl + 1);
      return line;
    }
    const std::int64_t left = deadline - mono_ns();
    if (left <= 0 || out_fd_ < 0) break;
    pollfd p{out_fd_, POLLIN, 0};
    const int r = poll(&p, 1, static_cast<int>(left / 1'000'000 + 1));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) continue;
    char buf[512];
    const ssize_t n = read(out_fd_, buf, sizeof buf);
    if (n <= 0) throw std::runtime_error("the child process closed its output");
    pending_.append(buf, static_cast<std::size_t>(n));
  }
  throw std::runtime_error("no line from the child process within " + std::to_string(timeout_ns / 1'000'000) + " ms");
}

int ChildProcess::stop() {
  int status = -1;
  if (pid_ > 0) {
    kill(pid_, SIGTERM);
    const std::int64_t deadline = mono_ns() + 2'000'000'000;
    pid_t r = 0;
    while ((r = waitpid(pid_, &status, WNOHANG)) == 0 && mono_ns() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (r == 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, &status, 0);
    }
    pid_ = -1;
  }
  if (out_fd_ >= 0) {
    close(out_fd_);
    out_fd_ = -1;
  }
  return status;
}

std::string executable_dir() {
  std::error_code ec;
  const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : p.parent_path().string();
}

}  // namespace tern::fcu
