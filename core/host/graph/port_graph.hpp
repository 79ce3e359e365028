// core/host/graph/port_graph.hpp: the port graph: which output feeds which input, checked and ordered.
//
// A pure function of the ports the instances declared (names, topics after remaps, message
// types): building and testing it needs Input<T>/Output<T> objects, no plugin library.
//   topics   every topic a port names, in order of first appearance (instance by instance,
//            outputs before inputs): its writers (outputs) and readers (inputs)
//   checks   at most one writer per topic, except controllers behind the phase router
//            ("routed" nodes), which may share a topic since only the active one is bound;
//            writers and readers of a topic carry one message type (name and layout
//            fingerprint); every required input has a writer
//   host     outputs the host offers itself (runtime mission edits) feed a topic that some
//            input reads and no node writes
//   order    I/O nodes first (config order), then producers before consumers; in a cycle the
//            earliest node not yet placed goes first, and its inputs whose producers run later
//            read the previous tick's message (feedback edges)
//   binding  bind() points every input at its topic's writer; on a routed topic, at the active
//            controller's output, or at nothing when no controller is active
// Errors are ConfigError, one line starting with the config file's path.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tern/port.hpp"
#include "tern/reflect.hpp"

namespace tern::core {

/// One instance as the graph sees it: its name and declared ports.
struct PortNode {
  std::string name;     ///< instance name ("ekf"), for messages
  bool io = false;      ///< an I/O plugin (simulator, FCU link): runs first in every tick
  bool routed = false;  ///< a controller behind the phase router
  std::vector<OutputBase*> outputs;
  std::vector<InputBase*> inputs;
};

struct GraphTopic {
  std::string name;
  std::string type_name;  ///< the writers' message type ("" when nobody writes)
  std::uint64_t fingerprint = 0;
  std::size_t msg_size = 0;                                  ///< bytes
  std::vector<reflect::Column> columns;                      ///< log columns of the message type
  std::vector<std::pair<std::size_t, OutputBase*>> writers;  ///< (node, port)
  std::vector<std::pair<std::size_t, InputBase*>> readers;   ///< (node, port)
  bool routed = false;                                       ///< written by routed controllers only
  const OutputBase* host_writer = nullptr;                   ///< written by the host itself
  const OutputBase* current = nullptr;                       ///< the writer the readers are bound to (nullptr: none)
  bool written() const { return !writers.empty() || host_writer != nullptr; }
};

/// A data dependency: node `from` writes `topic`, node `to` reads it.
struct GraphEdge {
  std::size_t from, to;
  std::string topic;
  bool feedback = false;  ///< `to` runs before `from` in a tick: it reads the previous tick's message
};

/// Whether every required input must have a producer: `tern params` lists the parameters of a
/// replay's config (configs/replay/), whose inputs a sensor log feeds, without one.
enum class Producers : std::uint8_t { required, not_checked };

class PortGraph {
 public:
  PortGraph() = default;
  /// Collects the topics of `nodes` (indices into `nodes` name the nodes everywhere below),
  /// checks them, offers `host_outputs` and orders the schedule. Each writer keeps as many
  /// messages as its deepest reader's queue (OutputBase::keep_history, tern/port.hpp). Binds
  /// nothing. Throws ConfigError ("<file>: topic 'actuators' has 2 writers: ...", "<file>: input
  /// 'ekf.imu' (topic 'imu', ...) has no producer ..." unless `producers` is not_checked).
  PortGraph(const std::vector<PortNode>& nodes, const std::vector<const OutputBase*>& host_outputs, const std::filesystem::path& file,
            Producers producers = Producers::required);

  const std::vector<GraphTopic>& topics() const { return topics_; }
  const std::vector<GraphEdge>& edges() const { return edges_; }
  /// Node indices in the order they step within a tick.
  const std::vector<std::size_t>& order() const { return order_; }
  /// The topic named `name`, or nullptr.
  const GraphTopic* find(const std::string& name) const;
  /// The output `topic`'s readers are bound to, if its writers publish a T; nullptr when the
  /// topic is missing, carries another type or has no bound writer.
  template <class T>
  const OutputBase* writer_of(const std::string& topic) const {
    const GraphTopic* t = find(topic);
    return t != nullptr && t->fingerprint == reflect::fingerprint<T>() ? t->current : nullptr;
  }
  /// Whether `host_output` (one of the constructor's) feeds a topic.
  bool offers(const OutputBase* host_output) const;
  /// Whether node `reader` reads `topic` over a feedback edge.
  bool feedback(std::size_t reader, const std::string& topic) const;
  /// "instance.port" of a port of node `node`.
  std::string port_id(std::size_t node, const PortBase& port) const;
  /// One line per topic: "  name [type] (routed): writers -> readers (feedback ...)".
  std::string describe_topics() const;

  /// Binds every input to its topic's writer; routed topics to node `active`'s outputs (nullopt:
  /// routed topics stay unbound).
  void bind(std::optional<std::size_t> active);
  /// Rebinds the routed topics to node `active`'s outputs (nullopt: unbound), and a plugin's
  /// topic that route_topic() took over back to its writer.
  void route(std::optional<std::size_t> active);
  /// Rebinds `topic` alone to `src`, an output of the host's of the topic's type (the state-loss
  /// recovery's and the flight termination's actuators); route() undoes it. `topic` is routed, or
  /// written by one plugin (the signal generator's `actuators`, downstream of the controller's
  /// remapped command: the host's command still reaches the aircraft). False otherwise.
  bool route_topic(const std::string& topic, const OutputBase* src);

 private:
  void collect(const std::vector<PortNode>& nodes);
  void check_writers(GraphTopic& t, const std::vector<PortNode>& nodes, const std::filesystem::path& file) const;
  void check_readers(const GraphTopic& t, const std::vector<std::string>& written, const std::filesystem::path& file) const;
  void offer(const OutputBase* out, const std::filesystem::path& file);
  static void keep_histories(const GraphTopic& t);
  void order_schedule(const std::vector<PortNode>& nodes);
  static void bind_readers(GraphTopic& t, const OutputBase* src);
  static const OutputBase* routed_writer(const GraphTopic& t, std::optional<std::size_t> active);

  std::vector<std::string> names_;  // node names
  std::vector<GraphTopic> topics_;
  std::vector<GraphEdge> edges_;
  std::vector<std::size_t> order_;
};

}  // namespace tern::core
