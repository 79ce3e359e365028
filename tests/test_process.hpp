// Runs the `tern` binary as a child process for the tests that signal it, limit it or read its
// exit status and console output.
#pragma once

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>

/// Starts TERN_BIN with `args`, stdout and stderr into `out`. `in_child` runs in the child
/// before exec (e.g. a resource limit).
inline pid_t spawn_tern(const std::vector<std::string>& args, const std::filesystem::path& out,
                        const std::function<void()>& in_child = {}) {
  const pid_t pid = fork();
  if (pid != 0) return pid;
  const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  dup2(fd, 1);
  dup2(fd, 2);
  if (in_child) in_child();
  std::vector<char*> argv{const_cast<char*>(TERN_BIN)};
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  execv(TERN_BIN, argv.data());
  _exit(127);
}

/// waitpid's status of `pid`.
inline int wait_for(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

/// Runs tern to the end; returns its exit code (-signal if a signal ended it).
inline int run_tern(const std::vector<std::string>& args, const std::filesystem::path& out, const std::function<void()>& in_child = {}) {
  const int status = wait_for(spawn_tern(args, out, in_child));
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

/// Polls `done` every 10 ms for up to `seconds`; returns its last answer.
inline bool wait_until(const std::function<bool()>& done, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}
