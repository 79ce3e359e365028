// tern_fcu_serial/process.hpp: a child process (the FCU emulator) whose standard output the
// parent reads line by line. Plain C++ (POSIX), no tern host types.
#pragma once

#include <cstdint>
#include <string>
#include <sys/types.h>
#include <vector>

namespace tern::fcu {

class ChildProcess {
 public:
  ChildProcess() = default;
  /// Starts argv[0] (a path) with argv; stdout goes to a pipe, stderr is inherited; `pass_fd`
  /// (if >= 0) becomes the child's file descriptor kPassedFd. Throws std::runtime_error naming
  /// the program if it cannot be started.
  explicit ChildProcess(const std::vector<std::string>& argv, int pass_fd = -1);
  static constexpr int kPassedFd = 3;
  ~ChildProcess();  ///< stop()
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// Reads the next line of the child's stdout (without '\n'), waiting at most timeout_ns.
  /// Throws std::runtime_error if the child closes its output or the time runs out.
  std::string read_line(std::int64_t timeout_ns);
  /// SIGTERM, then SIGKILL after 2 s; reaps the child. Returns its exit status (-1 if none).
  int stop();
  bool running() const { return pid_ > 0; }
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  int out_fd_ = -1;
  std::string pending_;
};

/// Directory of the running executable (/proc/self/exe), e.g. build/bin for the tern host.
std::string executable_dir();

}  // namespace tern::fcu
