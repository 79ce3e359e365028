#include "runners/isolated_plugin.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <new>

#include <boost/date_time/posix_time/posix_time_types.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "config/error.hpp"
#include "graph/scheduler.hpp"

namespace tern::core {

namespace {

using isolation::Command;

constexpr int kChildFd = 3;                     // the segment's descriptor in the child
constexpr Nanos kSpawnBudget = 30'000'000'000;  // loading the library and configure(): 30 s
constexpr Nanos kQuitBudget = 1'000'000'000;    // a child that does not quit in 1 s is killed
constexpr long kPollMs = 5;                     // a dead child is noticed within this

std::string signal_name(int sig) {
  switch (sig) {
    case SIGSEGV: return "SIGSEGV";
    case SIGABRT: return "SIGABRT";
    case SIGBUS: return "SIGBUS";
    case SIGFPE: return "SIGFPE";
    case SIGILL: return "SIGILL";
    case SIGKILL: return "SIGKILL";
    case SIGTERM: return "SIGTERM";
    case SIGINT: return "SIGINT";
    case SIGPIPE: return "SIGPIPE";
    default: return fmt::format("signal {}", sig);
  }
}

// `tern-isolate`: beside the running binary, else in the build tree, else installed.
fs::path isolate_binary() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  for (const fs::path& p :
       {ec ? fs::path() : self.parent_path() / "tern-isolate", fs::path(TERN_ISOLATE_BUILD_PATH), fs::path(TERN_ISOLATE_INSTALL_PATH)})
    if (!p.empty() && ::access(p.c_str(), X_OK) == 0) return p;
  throw ConfigError("isolate: the helper 'tern-isolate' was not found beside " + self.string() + " nor at " + TERN_ISOLATE_BUILD_PATH);
}

// The shadow's parameter `p` calls `mark` when it changes (the shadow never runs its own callbacks).
void watch_param(ParamBase& p, std::function<void()> mark) {
  switch (p.kind()) {
    case ParamKind::boolean: static_cast<Param<bool>&>(p).on_change([mark](const bool&) { mark(); }); break;
    case ParamKind::integer: static_cast<Param<std::int64_t>&>(p).on_change([mark](const std::int64_t&) { mark(); }); break;
    case ParamKind::real: static_cast<Param<double>&>(p).on_change([mark](const double&) { mark(); }); break;
    case ParamKind::text: static_cast<Param<std::string>&>(p).on_change([mark](const std::string&) { mark(); }); break;
    case ParamKind::vector: static_cast<Param<std::vector<double>>&>(p).on_change([mark](const std::vector<double>&) { mark(); }); break;
  }
}

}  // namespace

IsolatedPlugin::IsolatedPlugin(std::unique_ptr<Plugin> shadow, Context& ctx, IsolationSpec spec)
    : shadow_(std::move(shadow)), spec_(std::move(spec)) {
  attach(&ctx);
  present_ports_of(*shadow_);
  if (inputs().size() + outputs().size() > isolation::kMaxPorts)
    throw ConfigError(fmt::format("isolate {}: {} ports, at most {} can cross to a child process", spec_.instance,
                                  inputs().size() + outputs().size(), isolation::kMaxPorts));
  const auto check = [this](const PortBase* p) {
    if (!isolation::message_is_bitwise(p->type().fingerprint))
      throw ConfigError(
          fmt::format("isolate {}: port '{}' carries '{}', not a standard message of plain bytes: it cannot cross to a child process",
                      spec_.instance, p->name(), p->type().name));
  };
  for (const PortBase* p : inputs()) check(p);
  for (const PortBase* p : outputs()) check(p);
  dirty_.assign(params().size(), 0);
  for (std::size_t i = 0; i < params().size(); ++i) watch_param(*params()[i], [this, i] { dirty_[i] = 1; });
  map_segment();
  spawn();
}

IsolatedPlugin::~IsolatedPlugin() {
  end_child();
  if (map_ != nullptr) ::munmap(map_, size_);
  if (fd_ >= 0) ::close(fd_);
}

// ---- the child's life -------------------------------------------------------------------------

void IsolatedPlugin::map_segment() {
  std::vector<std::size_t> sizes;
  for (const PortBase* p : inputs()) sizes.push_back(p->type().size);
  for (const PortBase* p : outputs()) sizes.push_back(p->type().size);
  size_ = isolation::segment_size(sizes);
  fd_ = ::memfd_create(("tern-isolate-" + spec_.instance).c_str(), MFD_CLOEXEC);
  if (fd_ < 0 || ::ftruncate(fd_, static_cast<off_t>(size_)) != 0)
    throw ConfigError(fmt::format("isolate {}: cannot create {} bytes of shared memory: {}", spec_.instance, size_, std::strerror(errno)));
  map_ = ::mmap(nullptr, size_, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, 0);
  if (map_ == MAP_FAILED) {
    map_ = nullptr;
    throw ConfigError(fmt::format("isolate {}: cannot map shared memory: {}", spec_.instance, std::strerror(errno)));
  }
  const auto offsets = isolation::port_offsets(sizes);
  h_ = new (map_) isolation::Header();
  h_->n_inputs = static_cast<std::uint32_t>(inputs().size());
  h_->n_outputs = static_cast<std::uint32_t>(outputs().size());
  std::vector<const PortBase*> ports(inputs().begin(), inputs().end());
  ports.insert(ports.end(), outputs().begin(), outputs().end());
  for (std::size_t k = 0; k < ports.size(); ++k) {
    auto& s = h_->ports[k];
    isolation::put_text(s.name, sizeof s.name, ports[k]->name());
    s.fingerprint = ports[k]->type().fingerprint;
    s.offset = offsets[k];
    s.size = static_cast<std::uint32_t>(sizes[k]);
  }
}

void IsolatedPlugin::spawn() {
  const fs::path exe = isolate_binary();
  const std::vector<std::string> args = {exe.string(),    std::to_string(kChildFd), spec_.config_file.string(),
                                         spec_.instance,  spec_.library.string(),   std::to_string(spec_.seed),
                                         spec_.fleet_part};
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  // a fresh child: no command pending, no reply
  while (h_->go.try_wait()) {
  }
  while (h_->done.try_wait()) {
  }
  h_->failed = h_->end_requested = h_->text_used = h_->log_used = h_->log_dropped = 0;
  for (std::size_t k = 0; k < inputs().size(); ++k) h_->ports[k].seq = 0;
  copied_src_.assign(inputs().size(), nullptr);
  copied_seq_.assign(inputs().size(), 0);
  seq_base_.clear();
  for (const auto* o : outputs()) seq_base_.push_back(o->sequence());
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) throw ConfigError(fmt::format("isolate {}: fork failed: {}", spec_.instance, std::strerror(errno)));
  if (pid == 0) {  // async-signal-safe calls only, until exec
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(126);
    struct sigaction ign {};
    ign.sa_handler = SIG_IGN;
    ::sigaction(SIGINT, &ign, nullptr);
    ::sigaction(SIGTERM, &ign, nullptr);
    ::sigaction(SIGHUP, &ign, nullptr);
    if (fd_ == kChildFd)
      ::fcntl(fd_, F_SETFD, 0);
    else
      ::dup2(fd_, kChildFd);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  pid_ = pid;
  failure_.clear();
  if (!wait_done(kSpawnBudget))
    throw ConfigError(fmt::format("isolate {}: the child process failed while loading: {}", spec_.instance, failure_));
  if (h_->failed) {
    const std::string why(h_->text, h_->text_used);
    end_child();
    throw ConfigError(fmt::format("isolate {}: {}", spec_.instance, why));
  }
  h_->log_used = h_->log_dropped = h_->end_requested = 0;  // the shadow's configure() logged the same lines
  send_params(true);
}

void IsolatedPlugin::end_child() {
  if (pid_ <= 0) return;
  h_->command = Command::quit;
  h_->go.post();
  const std::int64_t t0 = wall_ns();
  int status = 0;
  while (::waitpid(pid_, &status, WNOHANG) == 0) {
    if (wall_ns() - t0 > kQuitBudget) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, &status, 0);
      break;
    }
    ::usleep(1000);
  }
  pid_ = -1;
}

// ---- one call -----------------------------------------------------------------------------------

bool IsolatedPlugin::wait_done(Nanos budget) {
  const std::int64_t t0 = wall_ns();
  for (int spins = 0; spins < 200; ++spins)
    if (h_->done.try_wait()) return true;
  for (;;) {
    const auto deadline = boost::posix_time::microsec_clock::universal_time() + boost::posix_time::milliseconds(kPollMs);
    if (h_->done.timed_wait(deadline)) return true;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      failure_ = WIFSIGNALED(status) ? fmt::format("isolated instance {} died: {}", spec_.instance, signal_name(WTERMSIG(status)))
                                     : fmt::format("isolated instance {} exited with status {}", spec_.instance, WEXITSTATUS(status));
      return false;
    }
    if (wall_ns() - t0 > budget) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, &status, 0);
      pid_ = -1;
      failure_ =
          fmt::format("isolated instance {} hung: no reply within {:.3f} s, killed with SIGKILL", spec_.instance, to_seconds(budget));
      return false;
    }
  }
}

void IsolatedPlugin::copy_inputs() {
  for (std::size_t k = 0; k < inputs().size(); ++k) {
    const InputBase* in = inputs()[k];
    auto& s = h_->ports[k];
    const OutputBase* src = in->source();
    s.bound = src != nullptr;
    s.updated = in->updated();
    s.seq = src ? src->sequence() : 0;
    if (src && (src != copied_src_[k] || src->sequence() != copied_seq_[k])) {
      std::memcpy(base() + s.offset, src->data(), s.size);
      copied_src_[k] = src;
      copied_seq_[k] = src->sequence();
    }
  }
}

void IsolatedPlugin::copy_outputs() {
  for (std::size_t k = 0; k < outputs().size(); ++k) {
    const auto& s = h_->ports[inputs().size() + k];
    const std::uint64_t seq = s.seq + seq_base_[k];
    if (seq != outputs()[k]->sequence()) outputs()[k]->publish_copy(base() + s.offset, seq);
  }
}

// Log lines and an end request of the last reply, to the instance's logger and context.
void IsolatedPlugin::deliver_reply() {
  auto log = context().logger();
  for (const auto& [level, line] : isolation::read_log(*h_)) log->log(static_cast<spdlog::level::level_enum>(level), line);
  if (h_->log_dropped > 0) log->warn("{} log lines of the isolated child did not fit the channel and were dropped", h_->log_dropped);
  if (h_->end_requested) context().end_flight(h_->end_reason, h_->end_detail);
  h_->log_used = h_->log_dropped = h_->end_requested = 0;
}

void IsolatedPlugin::send_params(bool all) {
  std::vector<std::pair<std::uint32_t, ParamValue>> changes;
  for (std::size_t i = 0; i < params().size(); ++i)
    if (all || dirty_[i]) changes.emplace_back(static_cast<std::uint32_t>(i), params()[i]->value());
  dirty_.assign(params().size(), 0);
  if (changes.empty()) return;
  h_->text_used = isolation::encode_params(changes, h_->text);
  call(Command::set_params);
}

void IsolatedPlugin::call(Command c) {
  if (pid_ <= 0)
    throw IsolatedFailure(failure_.empty() ? fmt::format("isolated instance {} has no child process", spec_.instance) : failure_);
  if (c != Command::set_params && std::find(dirty_.begin(), dirty_.end(), 1) != dirty_.end()) send_params(false);
  copy_inputs();
  h_->command = c;
  h_->failed = 0;
  h_->go.post();
  if (!wait_done(spec_.hard_budget)) throw IsolatedFailure(failure_);
  copy_outputs();
  deliver_reply();
  if (h_->failed) throw std::runtime_error(std::string(h_->text, h_->text_used));
}

// ---- the plugin's life --------------------------------------------------------------------------

void IsolatedPlugin::start() {
  if (pid_ <= 0) spawn();  // failed last flight
  summary_.clear();
  call(Command::start);
}

void IsolatedPlugin::step(Nanos now) {
  h_->now = now;
  call(Command::step);
}

void IsolatedPlugin::reset() {
  if (pid_ <= 0) {
    spawn();  // a fresh process is a reset plugin
    return;
  }
  call(Command::reset);
}

void IsolatedPlugin::take_over(const msg::Actuators& last_command) {
  h_->take_over = last_command;
  call(Command::take_over);
}

void IsolatedPlugin::stop() {
  if (pid_ <= 0) return;  // failed: nothing to stop, no summary
  call(Command::stop);
  summary_.clear();
  const std::string text(h_->text, h_->text_used);
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t tab = text.find('\t', at);
    if (tab == std::string::npos || tab + 1 + sizeof(double) > text.size()) break;
    double v = 0;
    std::memcpy(&v, text.data() + tab + 1, sizeof v);
    summary_.emplace_back(text.substr(at, tab - at), v);
    at = tab + 1 + sizeof v;
  }
}

}  // namespace tern::core
