// A plugin that logs, built with the SDK's own header only (no spdlog include): log() must be
// usable as it is (issue 22). test_log.cpp checks what it wrote.
#include "tern/plugin.hpp"

namespace {
class Chatty final : public tern::Plugin {
 public:
  void configure() override {}
  void step(tern::Nanos now) override {
    log().info("step at {:.2f} s, count {}", tern::to_seconds(now), ++count_);
    log().warn("a warning");
  }

 private:
  int count_ = 0;
};
}  // namespace

std::unique_ptr<tern::Plugin> make_chatty_plugin() { return std::make_unique<Chatty>(); }
