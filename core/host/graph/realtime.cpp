// A paced flight's thread settings and clock figures. See realtime.hpp.
#include "graph/realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

namespace tern::core {

namespace {

std::string failure(const std::string& option, const char* call, int err, const char* what_to_do) {
  return fmt::format("{}: {} failed ({}){}", option, call, std::strerror(err), what_to_do);
}

// The flight thread's own fault counts (the log writer's are not the loop's).
void thread_faults(long& minor, long& major) {
  rusage u{};
  if (getrusage(RUSAGE_THREAD, &u) != 0) return;
  minor = u.ru_minflt;
  major = u.ru_majflt;
}

double us(Nanos ns) { return static_cast<double>(ns) * 1e-3; }

}  // namespace

std::string apply_realtime(const RealtimeOptions& o) {
  constexpr const char* kPermit =
      ": run as root, or grant rtprio in /etc/security/limits.conf or CAP_SYS_NICE (docs/companion-computer.md)";
  if (o.priority != 0) {
    const int lo = sched_get_priority_min(SCHED_FIFO), hi = sched_get_priority_max(SCHED_FIFO);
    if (o.priority < lo || o.priority > hi)
      return fmt::format("--rt-priority {}: SCHED_FIFO priorities on this system are {}..{}", o.priority, lo, hi);
    sched_param p{};
    p.sched_priority = o.priority;
    if (const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &p); err != 0)
      return failure(fmt::format("--rt-priority {}", o.priority), "pthread_setschedparam(SCHED_FIFO)", err, err == EPERM ? kPermit : "");
  }
  if (o.cpu >= 0) {
    if (o.cpu >= CPU_SETSIZE) return fmt::format("--cpu {}: beyond the {} CPUs an affinity mask holds", o.cpu, CPU_SETSIZE);
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(o.cpu, &set);
    if (const int err = pthread_setaffinity_np(pthread_self(), sizeof(set), &set); err != 0)
      return failure(fmt::format("--cpu {}", o.cpu), "pthread_setaffinity_np", err,
                     err == EINVAL ? ": no such CPU, or not one this process may use (see nproc, taskset -p $$)" : "");
  }
  if (o.lock_memory && mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    const int err = errno;
    return failure("--mlockall", "mlockall(MCL_CURRENT | MCL_FUTURE)", err,
                   err == EPERM || err == ENOMEM
                       ? ": run as root, or raise memlock in /etc/security/limits.conf (ulimit -l) or grant CAP_IPC_LOCK"
                       : "");
  }
  return "";
}

std::string describe(const RealtimeOptions& o) {
  return fmt::format("{}, {}, memory {}{}", o.priority != 0 ? fmt::format("SCHED_FIFO {}", o.priority) : std::string("SCHED_OTHER"),
                     o.cpu >= 0 ? fmt::format("CPU {}", o.cpu) : std::string("any CPU"), o.lock_memory ? "locked" : "not locked",
                     o.speed != 1.0 ? fmt::format(", {:g}x wall time", o.speed) : std::string());
}

void RealtimeStats::begin(std::int64_t now) {
  tick_start_ = now;
  thread_faults(minor0_, major0_);
}

bool RealtimeStats::work_done(std::int64_t now, std::int64_t deadline) {
  work_.add(now - tick_start_);
  if (now <= deadline) return false;
  ++misses_;
  tick_start_ = now;  // no sleep: the next tick starts at once
  return true;
}

void RealtimeStats::woke(std::int64_t now, std::int64_t deadline) {
  wake_.add(now - deadline);
  tick_start_ = now;
}

void RealtimeStats::end() {
  long minor = minor0_, major = major0_;
  thread_faults(minor, major);
  minor_ = minor - minor0_;
  major_ = major - major0_;
}

nlohmann::ordered_json RealtimeStats::to_json(const RealtimeOptions& o) const {
  auto figures = [](const StepStats& s) {
    return nlohmann::ordered_json{
        {"samples", s.steps}, {"p50_us", us(s.percentile(0.5))}, {"p99_us", us(s.percentile(0.99))}, {"max_us", us(s.max_ns)}};
  };
  nlohmann::ordered_json j;
  j["scheduling"] = describe(o);
  j["ticks"] = ticks();
  j["deadline_misses"] = misses_;
  j["deadline_miss_share"] = ticks() > 0 ? static_cast<double>(misses_) / static_cast<double>(ticks()) : 0.0;
  j["wake_up_latency"] = figures(wake_);
  j["work_per_tick"] = figures(work_);
  j["page_faults_minor"] = minor_;
  j["page_faults_major"] = major_;
  j["rule"] =
      "wall clock: work from a tick's start to the end of its steps; a tick whose work ends after its end time is a miss; else the "
      "thread sleeps to it and wakes up late by the latency; percentiles are histogram bucket bounds (within 19 %); page faults of the "
      "flight thread (getrusage RUSAGE_THREAD)";
  return j;
}

std::string RealtimeStats::line(const RealtimeOptions& o) const {
  return fmt::format(
      "real time: {}; {} ticks, {} deadline misses ({:.3f} %); wake-up p50 {:.0f} us, p99 {:.0f} us, max {:.0f} us; work p50 {:.0f} us, "
      "p99 {:.0f} us, max {:.0f} us; page faults {} minor, {} major\n",
      describe(o), ticks(), misses_, ticks() > 0 ? 100.0 * static_cast<double>(misses_) / static_cast<double>(ticks()) : 0.0,
      us(wake_.percentile(0.5)), us(wake_.percentile(0.99)), us(wake_.max_ns), us(work_.percentile(0.5)), us(work_.percentile(0.99)),
      us(work_.max_ns), minor_, major_);
}

}  // namespace tern::core
