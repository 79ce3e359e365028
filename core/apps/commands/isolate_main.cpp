// tern-isolate: the child process of an isolated instance (isolated_plugin.hpp). Not for people:
// the host starts it as
//   tern-isolate FD CONFIG INSTANCE LIBRARY SEED
// with FD the shared-memory segment (isolation_channel.hpp) the host has laid out. It loads the
// mission config, builds the instance from LIBRARY exactly as the host does (configure_instance:
// same parameters, remaps and seed), checks that its ports are the host's (name and fingerprint,
// in order), replies `ready`, then runs the host's commands one at a time until `quit`.
// Exit status: 0 after quit, 1 when the instance could not be built (the reason is the reply's
// text), 2 when the segment itself is unusable (the reason goes to stderr).
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

#include "config/config.hpp"
#include "config/error.hpp"
#include "fleet/fleet_config.hpp"
#include "graph/instances.hpp"
#include "runners/isolation_channel.hpp"
#include "graph/loader.hpp"

namespace tern::core {
namespace {

using isolation::Command;
using isolation::Header;

// Log lines go into the reply's log area; the host hands them to the instance's logger.
class ChannelSink final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  explicit ChannelSink(Header& h) : h_(h) {}

 protected:
  void sink_it_(const spdlog::details::log_msg& m) override {
    isolation::append_log(h_, static_cast<int>(m.level), std::string(m.payload.data(), m.payload.size()));
  }
  void flush_() override {}

 private:
  Header& h_;
};

// The child's view of a host output: the message bytes in the segment, the host's sequence number.
class ChannelOutput final : public OutputBase {
 public:
  // clear(): nothing to do here; the host clears its output and the segment follows it
  ChannelOutput(const MsgType& type, const void* data) : OutputBase(type, data, [](void*) {}) {}
  void set_sequence(std::uint64_t s) { seq_ = s; }
};

class Child {
 public:
  Child(Header& h, char* base) : h_(h), base_(base) {}

  /// `part`: a multi-vehicle mission's vehicle or "coordination" (fleet_config.hpp), "" for a
  /// one-vehicle mission.
  void build(const fs::path& config_file, const std::string& part, const std::string& instance, const fs::path& library,
             std::uint64_t seed);
  /// Runs commands until quit.
  void serve();

 private:
  void check_ports() const;
  void inputs_in();
  void outputs_out();
  void run(Command c);
  void set_params();
  void write_summary();

  Header& h_;
  char* base_;
  MissionConfig config_;
  Instance inst_;
  std::shared_ptr<spdlog::logger> log_;
  std::vector<std::unique_ptr<ChannelOutput>> sources_;  // per input
};

void Child::build(const fs::path& config_file, const std::string& part, const std::string& instance, const fs::path& library,
                  std::uint64_t seed) {
  config_ = part.empty() ? load_config(config_file) : load_fleet_part(config_file, part);
  const InstanceConfig* ic = nullptr;
  for (const auto& c : config_.plugins)
    if (c.name == instance) ic = &c;
  if (ic == nullptr) throw ConfigError(config_file.string() + ": no plugin instance named '" + instance + "'");
  inst_.cfg = *ic;
  inst_.lib = open_plugin(library);
  inst_.info = inst_.lib->info();
  inst_.source = library;
  inst_.plugin = inst_.lib->create();
  auto sink = std::make_shared<ChannelSink>(h_);
  log_ = std::make_shared<spdlog::logger>("tern-isolate", sink);
  configure_instance(inst_, InstanceSetup{config_, seed, sink, false, *log_});
  check_ports();
  for (auto* in : inst_.plugin->inputs()) {
    const auto& s = h_.ports[sources_.size()];
    sources_.push_back(std::make_unique<ChannelOutput>(in->type(), base_ + s.offset));
  }
}

void Child::check_ports() const {
  const auto& ins = inst_.plugin->inputs();
  const auto& outs = inst_.plugin->outputs();
  if (ins.size() != h_.n_inputs || outs.size() != h_.n_outputs)
    throw ConfigError(fmt::format("the child's plugin has {} inputs and {} outputs, the host's {} and {}", ins.size(), outs.size(),
                                  h_.n_inputs, h_.n_outputs));
  std::vector<const PortBase*> ports(ins.begin(), ins.end());
  ports.insert(ports.end(), outs.begin(), outs.end());
  for (std::size_t k = 0; k < ports.size(); ++k) {
    const auto& s = h_.ports[k];
    if (ports[k]->name() != s.name || ports[k]->type().fingerprint != s.fingerprint || ports[k]->type().size != s.size)
      throw ConfigError(fmt::format("port {} of the child's plugin is '{}' ({}), the host's is '{}'", k, ports[k]->name(),
                                    ports[k]->type().name, s.name));
  }
}

// The host's inputs as this plugin's: bound or not, the latest message, and updated() agreeing.
void Child::inputs_in() {
  const auto& ins = inst_.plugin->inputs();
  for (std::size_t k = 0; k < ins.size(); ++k) {
    const auto& s = h_.ports[k];
    ChannelOutput* src = sources_[k].get();
    src->set_sequence(s.seq);
    if ((ins[k]->source() != nullptr) != (s.bound != 0)) ins[k]->bind(s.bound ? src : nullptr);
    if (ins[k]->updated() == (s.updated != 0)) continue;
    if (s.updated)
      ins[k]->bind(src);  // seen 0: updated, since seq > 0
    else
      ins[k]->mark_seen();
  }
}

void Child::outputs_out() {
  const auto& outs = inst_.plugin->outputs();
  for (std::size_t k = 0; k < outs.size(); ++k) {
    auto& s = h_.ports[h_.n_inputs + k];
    if (s.seq == outs[k]->sequence()) continue;
    std::memcpy(base_ + s.offset, outs[k]->data(), s.size);
    s.seq = outs[k]->sequence();
  }
}

void Child::set_params() {
  const auto& params = inst_.plugin->params();
  for (const auto& [index, value] : isolation::decode_params(h_.text, h_.text_used)) {
    if (index >= params.size()) throw std::runtime_error(fmt::format("parameter index {} out of range", index));
    if (params[index]->value() != value) params[index]->set(value);
  }
}

void Child::write_summary() {
  std::string text;
  for (const auto& [name, v] : inst_.plugin->summary()) {
    text += name + '\t';
    text.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  if (text.size() > isolation::kTextBytes) text.resize(0);
  std::memcpy(h_.text, text.data(), text.size());
  h_.text_used = static_cast<std::uint32_t>(text.size());
}

void Child::run(Command c) {
  Plugin& p = *inst_.plugin;
  switch (c) {
    case Command::start: p.start(); break;
    case Command::step:
      p.step(h_.now);
      for (auto* in : p.inputs()) in->mark_seen();
      break;
    case Command::reset: p.reset(); break;
    case Command::take_over: p.take_over(h_.take_over); break;
    case Command::stop:
      p.stop();
      write_summary();
      break;
    case Command::set_params: set_params(); break;
    default: throw std::runtime_error(fmt::format("unknown command {}", static_cast<unsigned>(c)));
  }
}

void Child::serve() {
  for (;;) {
    h_.go.wait();
    const Command c = h_.command;
    if (c == Command::quit) return;
    inputs_in();
    std::string error;
    try {
      run(c);
    } catch (const std::exception& e) {
      error = e.what();
    } catch (...) {
      error = "unknown exception";
    }
    outputs_out();
    if (auto end = inst_.take_end_request()) {
      h_.end_requested = 1;
      isolation::put_text(h_.end_reason, sizeof h_.end_reason, end->reason);
      isolation::put_text(h_.end_detail, sizeof h_.end_detail, end->detail);
    }
    if (!error.empty()) {
      h_.failed = 1;
      isolation::put_text(h_.text, isolation::kTextBytes, error);
      h_.text_used = static_cast<std::uint32_t>(std::strlen(h_.text));
    }
    h_.done.post();
  }
}

}  // namespace
}  // namespace tern::core

int main(int argc, char** argv) {
  using namespace tern::core;
  if (argc != 7) {
    std::fprintf(stderr, "tern-isolate: started by the tern host only (FD CONFIG INSTANCE LIBRARY SEED FLEET_PART)\n");
    return 2;
  }
  const int fd = std::atoi(argv[1]);
  struct stat st {};
  if (::fstat(fd, &st) != 0 || static_cast<std::size_t>(st.st_size) < sizeof(isolation::Header)) {
    std::fprintf(stderr, "tern-isolate: descriptor %d is not the host's shared memory\n", fd);
    return 2;
  }
  void* map = ::mmap(nullptr, static_cast<std::size_t>(st.st_size), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  if (map == MAP_FAILED || static_cast<isolation::Header*>(map)->magic != isolation::kMagic) {
    std::fprintf(stderr, "tern-isolate: cannot map the host's shared memory\n");
    return 2;
  }
  auto& h = *static_cast<isolation::Header*>(map);
  Child child(h, static_cast<char*>(map));
  try {
    child.build(argv[2], argv[6], argv[3], argv[4], std::stoull(argv[5]));
  } catch (const std::exception& e) {
    h.failed = 1;
    isolation::put_text(h.text, isolation::kTextBytes, e.what());
    h.text_used = static_cast<std::uint32_t>(std::strlen(h.text));
    h.done.post();
    return 1;
  }
  h.done.post();  // ready
  child.serve();
  return 0;
}
