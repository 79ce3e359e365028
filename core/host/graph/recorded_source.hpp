// core/host/graph/recorded_source.hpp: what a replay flies instead of the config's I/O plugins: a
// built-in I/O instance named `replay` that plays a recorded flight's topics into the port graph
// (`tern replay`; the applications' one is apps/replay/replay_source.hpp, a sensor log's tables).
// The host only makes it (HostOptions::replay), runs it as any I/O instance and asks where the
// recording ends.
#pragma once

#include <functional>
#include <memory>

#include "tern/plugin.hpp"

namespace tern::core {

class RecordedSource : public Plugin {
 public:
  /// Flight time of the last recorded IMU sample (0 if none): the replay flies until the first
  /// tick at or after it (Host::replay_end()), so that sample is played.
  virtual Nanos end_time() const = 0;
};

/// Makes a replay's source, once per build of the host.
using RecordedSourceFactory = std::function<std::unique_ptr<RecordedSource>()>;

}  // namespace tern::core
