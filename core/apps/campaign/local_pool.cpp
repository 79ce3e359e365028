#include "local_pool.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <ctime>
#include <map>
#include <string>
#include <vector>

#include "config/error.hpp"

namespace tern::campaign {

namespace {

volatile std::sig_atomic_t g_signal = 0;

void on_signal(int s) { g_signal = s; }

pid_t spawn(const Job& job) {
  // built before fork: the child may only make async-signal-safe calls, and malloc is not one
  std::vector<char*> args;
  for (const auto& a : job.argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw core::ConfigError(std::string("cannot start a flight: fork: ") + std::strerror(errno));
  if (pid > 0) return pid;
  // child: only async-signal-safe calls until exec
  setpgid(0, 0);
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() != parent) _exit(127);
  signal(SIGINT, SIG_DFL);
  signal(SIGTERM, SIG_DFL);
  signal(SIGHUP, SIG_DFL);
  const int fd = open(job.console.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0) {
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    close(fd);
  }
  execv(args[0], args.data());
  _exit(127);
}

}  // namespace

void install_interrupt_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: the nap in run_local returns EINTR
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaction(s, &sa, nullptr);
}

int interrupted() { return g_signal; }

bool run_local(const std::vector<Job>& jobs, int workers, const std::function<void(std::size_t, int)>& on_done) {
  std::map<pid_t, std::size_t> running;  // pid -> job index
  std::size_t next = 0;
  bool stopping = false;
  while (next < jobs.size() || !running.empty()) {
    while (!stopping && g_signal == 0 && next < jobs.size() && running.size() < static_cast<std::size_t>(workers)) {
      running[spawn(jobs[next])] = jobs[next].index;
      ++next;
    }
    if (g_signal != 0 && !stopping) {
      stopping = true;
      next = jobs.size();
      for (const auto& [pid, idx] : running) kill(pid, SIGTERM);
    }
    if (running.empty()) break;
    // Poll rather than block: a signal landing between the g_signal test above and a blocking
    // waitpid would otherwise wait for a flight to end; here it waits at most one nap.
    int status = 0;
    const pid_t pid = waitpid(-1, &status, WNOHANG);
    if (pid == 0) {
      const timespec nap{0, 50'000'000};
      nanosleep(&nap, nullptr);  // EINTR on a signal: the loop sees it at once
      continue;
    }
    if (pid < 0) {
      if (errno == EINTR) continue;
      break;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const std::size_t idx = it->second;
    running.erase(it);
    on_done(idx, status);
  }
  return g_signal == 0;
}

}  // namespace tern::campaign
