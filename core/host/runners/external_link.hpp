// core/host/runners/external_link.hpp: the narrow interface between an external instance (external_plugin.hpp)
// and the DDS layer that carries its topics (core/apps/dds/src/external_link_dds.cpp), so that the host
// builds without DDS. Without a registered factory (tern built without Fast DDS) an external
// instance is a ConfigError.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "config/external_spec.hpp"
#include "tern/time.hpp"

namespace tern::core {

/// The DDS endpoints of one external instance: a writer per spec input, a reader per output.
class ExternalLink {
 public:
  virtual ~ExternalLink() = default;
  /// Waits up to `timeout` until every writer has matched a reader and every reader a writer;
  /// returns the DDS names of those still unmatched.
  virtual std::vector<std::string> wait_matched(std::chrono::milliseconds timeout) = 0;
  /// Publishes spec input `i`: `tern_msg` (of the binding's tern type), header stamp `stamp`
  /// (ROS time: the tick's sim time).
  virtual void publish(std::size_t i, const void* tern_msg, Nanos stamp) = 0;
  /// Takes spec output `o`'s sample stamped exactly `stamp` into `tern_msg` (of the binding's tern
  /// type, stamp = `stamp`), waiting up to `timeout`; older samples are dropped. False when none
  /// came in time. Throws std::runtime_error for a sample that cannot be converted (e.g. a
  /// rosflight Command in a mode other than pass-through).
  virtual bool take(std::size_t o, Nanos stamp, void* tern_msg, std::chrono::microseconds timeout) = 0;
  /// Without waiting: the newest sample of output `o` that came since the last take (any stamp;
  /// older ones are dropped) into `tern_msg`, stamped `stamp`. False when none came. Throws as take().
  virtual bool take_latest(std::size_t o, Nanos stamp, void* tern_msg) = 0;
};

using ExternalLinkFactory = std::function<std::unique_ptr<ExternalLink>(const ExternalSpec&, const MissionConfig&)>;
/// Registers the DDS layer's factory (tern's main() does, when built with DDS).
void set_external_link_factory(ExternalLinkFactory factory);
/// The registered factory (empty when none).
const ExternalLinkFactory& external_link_factory();

}  // namespace tern::core
