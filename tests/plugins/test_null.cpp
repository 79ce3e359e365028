// test_null: a plugin whose step does nothing, to measure the scheduler's own cost per step.
#include "tern/plugin.hpp"

namespace {
class TestNull final : public tern::Plugin {
 public:
  void configure() override {}
  void step(tern::Nanos) override { ++steps_; }
  std::vector<std::pair<std::string, double>> summary() const override { return {{"steps", static_cast<double>(steps_)}}; }

 private:
  long steps_ = 0;
};
}  // namespace

TERN_PLUGIN(TestNull, "test_null", tern::PluginKind::generic, "host test: does nothing")
