#include <doctest/doctest.h>

#include <memory>
#include <sstream>

#include <spdlog/sinks/ostream_sink.h>

#include "tern/testing/harness.hpp"

std::unique_ptr<tern::Plugin> make_chatty_plugin();  // log_plugin.cpp

TEST_CASE("log() in plugin code formats and writes through the instance's logger") {
  tern::testing::HarnessOptions options;
  options.instance = "chatty";
  tern::testing::Harness h(make_chatty_plugin(), {}, options);
  std::ostringstream out;
  auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(out);
  sink->set_pattern("%l %v");
  h.logger()->sinks().push_back(sink);
  h.step(tern::from_seconds(0.25));
  h.step(tern::from_seconds(0.5));
  h.logger()->sinks().pop_back();
  const std::string text = out.str();
  CHECK(text.find("info step at 0.25 s, count 1") != std::string::npos);
  CHECK(text.find("info step at 0.50 s, count 2") != std::string::npos);
  CHECK(text.find("warning a warning") != std::string::npos);
}
