// core/host/flight/held_messages.hpp: fields of a topic's message held from outside the flight
// (tern.Host.write, the learning environment's action replacing a controller's `actuators` or a
// loop's `controller_command`): after every step that publishes on the topic, the held fields
// replace the producer's values before any consumer reads them and before the log captures them,
// until released. With nothing held the flight is untouched (Host::run_tick checks empty()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "graph/port_graph.hpp"
#include "tern/port.hpp"

namespace tern::core {

class HeldMessages {
 public:
  /// Holds `fields` (log column name, value) on `topic`, whose messages are of type `type`,
  /// replacing what was held there. Throws ConfigError naming the topic and the field: an
  /// unknown field (with the message's fields listed), a value that is not finite or does not fit
  /// the field's type.
  void hold(const std::string& topic, const MsgType& type, const std::vector<std::pair<std::string, double>>& fields);
  /// Stops holding `topic`; false when nothing was held there.
  bool release(const std::string& topic);
  bool empty() const { return held_.empty(); }
  /// A new flight: every held topic is applied again from its producer's first message.
  void new_flight();
  /// After a step: every held topic whose producer in `graph` (its current one: the phase
  /// router's choice for `actuators`) published since the last call gets the held fields written
  /// into that message (same sequence number).
  void apply(const PortGraph& graph);

 private:
  struct Field {
    reflect::Column column;
    double value;
  };
  struct Held {
    std::string topic;
    std::vector<Field> fields;
    const OutputBase* applied_to = nullptr;  // the output last written, and its sequence then
    std::uint64_t applied_seq = 0;
    std::vector<std::byte> scratch;  // one message
  };
  std::vector<Held> held_;
};

}  // namespace tern::core
