#include "graph/port_graph.hpp"

#include <algorithm>

#include <map>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "config/error.hpp"

namespace tern::core {

PortGraph::PortGraph(const std::vector<PortNode>& nodes, const std::vector<const OutputBase*>& host_outputs,
                     const std::filesystem::path& file, Producers producers) {
  for (const auto& n : nodes) names_.push_back(n.name);
  collect(nodes);
  std::vector<std::string> written;
  for (const auto& t : topics_)
    if (!t.writers.empty()) written.push_back(t.name);
  for (const OutputBase* out : host_outputs) written.push_back(out->topic());  // offer() checks their readers
  for (auto& t : topics_) {
    check_writers(t, nodes, file);
    if (producers == Producers::required) check_readers(t, written, file);
    keep_histories(t);
  }
  for (const OutputBase* out : host_outputs) offer(out, file);
  order_schedule(nodes);
}

// Each writer holds as many messages as its deepest reader's queue reads (Input<T>::received()).
void PortGraph::keep_histories(const GraphTopic& t) {
  std::size_t depth = 1;
  for (const auto& [i, in] : t.readers) depth = std::max<std::size_t>(depth, in->queue_depth());
  for (const auto& [i, out] : t.writers) out->keep_history(depth);
}

std::string PortGraph::port_id(std::size_t node, const PortBase& port) const { return names_[node] + "." + port.name(); }

void PortGraph::collect(const std::vector<PortNode>& nodes) {
  std::map<std::string, std::size_t> by_name;
  auto topic_of = [&](const std::string& name) -> GraphTopic& {
    auto it = by_name.find(name);
    if (it == by_name.end()) {
      topics_.emplace_back().name = name;
      it = by_name.emplace(name, topics_.size() - 1).first;
    }
    return topics_[it->second];
  };
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    for (auto* out : nodes[i].outputs) topic_of(out->topic()).writers.emplace_back(i, out);
    for (auto* in : nodes[i].inputs) topic_of(in->topic()).readers.emplace_back(i, in);
  }
}

// One writer, or routed controllers only; all of one message type. Sets the topic's type.
void PortGraph::check_writers(GraphTopic& t, const std::vector<PortNode>& nodes, const std::filesystem::path& file) const {
  if (t.writers.empty()) return;
  bool all_routed = true;
  for (auto& [i, o] : t.writers) all_routed = all_routed && nodes[i].routed;
  if (t.writers.size() > 1 && !all_routed) {
    std::vector<std::string> ids;
    for (auto& [i, o] : t.writers) ids.push_back(port_id(i, *o));
    throw ConfigError(
        fmt::format("{}: topic '{}' has {} writers: {} (only controllers behind the phase router, "
                    "named in 'phases:', may share a topic; remap one of them)",
                    file.string(), t.name, ids.size(), fmt::join(ids, ", ")));
  }
  t.routed = all_routed;
  const auto& [i0, w0] = t.writers.front();
  t.type_name = std::string(w0->type().name);
  t.fingerprint = w0->type().fingerprint;
  t.msg_size = w0->type().size;
  t.columns = w0->type().columns();
  for (auto& [i, o] : t.writers) {
    if (o->type().fingerprint != t.fingerprint)
      throw ConfigError(fmt::format(
          "{}: topic '{}': writers disagree on the message type: {} publishes {} ({:016x}), {} publishes {} ({:016x})", file.string(),
          t.name, port_id(i0, *w0), t.type_name, t.fingerprint, port_id(i, *o), o->type().name, o->type().fingerprint));
  }
}

// Every required reader has a writer of its message type.
void PortGraph::check_readers(const GraphTopic& t, const std::vector<std::string>& written, const std::filesystem::path& file) const {
  for (auto& [i, in] : t.readers) {
    const std::string who = port_id(i, *in);
    if (t.writers.empty()) {
      if (in->need() == Need::optional || std::find(written.begin(), written.end(), t.name) != written.end()) continue;
      throw ConfigError(
          fmt::format("{}: input '{}' (topic '{}', {}) has no producer: no instance publishes '{}'{}; "
                      "add a plugin that does or remap the input",
                      file.string(), who, t.name, in->type().name, t.name, did_you_mean(t.name, written)));
    }
    if (in->type().fingerprint != t.fingerprint) {
      const bool same_name = in->type().name == t.type_name;
      throw ConfigError(fmt::format("{}: input '{}' expects {} ({:016x}) but topic '{}' carries {} ({:016x}) from '{}'{}", file.string(),
                                    who, in->type().name, in->type().fingerprint, t.name, t.type_name, t.fingerprint,
                                    port_id(t.writers[0].first, *t.writers[0].second),
                                    same_name ? ": same type name, different layout; rebuild both against the same SDK" : ""));
    }
  }
}

// A host output feeds its topic when some input reads it and no node writes it.
void PortGraph::offer(const OutputBase* out, const std::filesystem::path& file) {
  for (auto& t : topics_) {
    if (t.name != out->topic() || !t.writers.empty() || t.readers.empty()) continue;
    for (auto& [i, in] : t.readers)
      if (in->type().fingerprint != out->type().fingerprint)
        throw ConfigError(fmt::format("{}: input '{}' on topic '{}' expects {}, the host publishes {}", file.string(), port_id(i, *in),
                                      t.name, in->type().name, out->type().name));
    t.type_name = std::string(out->type().name);
    t.fingerprint = out->type().fingerprint;
    t.msg_size = out->type().size;
    t.columns = out->type().columns();
    t.host_writer = out;
  }
}

void PortGraph::order_schedule(const std::vector<PortNode>& nodes) {
  const std::size_t n = nodes.size();
  for (const auto& t : topics_)
    for (auto& [w, o] : t.writers)
      for (auto& [r, in] : t.readers)
        if (w != r) edges_.push_back({w, r, t.name, false});
  std::vector<bool> placed(n, false);
  for (std::size_t i = 0; i < n; ++i)
    if (nodes[i].io) {
      order_.push_back(i);
      placed[i] = true;
    }
  while (order_.size() < n) {
    std::optional<std::size_t> pick;
    for (std::size_t i = 0; i < n && !pick; ++i) {
      if (placed[i]) continue;
      bool ready = true;
      for (const auto& e : edges_)
        if (e.to == i && !placed[e.from]) ready = false;
      if (ready) pick = i;
    }
    if (!pick) {  // a cycle: the earliest node goes first, its open inputs are feedback
      for (std::size_t i = 0; i < n && !pick; ++i)
        if (!placed[i]) pick = i;
    }
    placed[*pick] = true;
    order_.push_back(*pick);
  }
  std::vector<std::size_t> pos(n);
  for (std::size_t k = 0; k < n; ++k) pos[order_[k]] = k;
  for (auto& e : edges_) e.feedback = pos[e.from] > pos[e.to];
}

const GraphTopic* PortGraph::find(const std::string& name) const {
  for (const auto& t : topics_)
    if (t.name == name) return &t;
  return nullptr;
}

bool PortGraph::offers(const OutputBase* host_output) const {
  for (const auto& t : topics_)
    if (t.host_writer == host_output) return true;
  return false;
}

bool PortGraph::feedback(std::size_t reader, const std::string& topic) const {
  for (const auto& e : edges_)
    if (e.to == reader && e.topic == topic && e.feedback) return true;
  return false;
}

std::string PortGraph::describe_topics() const {
  std::string s;
  for (const auto& t : topics_) {
    std::vector<std::string> w, r;
    for (auto& [i, o] : t.writers) w.push_back(port_id(i, *o));
    if (t.host_writer) w.push_back(t.host_writer->description().empty() ? "host" : "host: " + t.host_writer->description());
    for (auto& [i, in] : t.readers)
      r.push_back(port_id(i, *in) + (feedback(i, t.name) ? " (feedback: previous tick)" : "") +
                  (t.written() ? "" : " (optional, unconnected)"));
    s += fmt::format("  {} [{}]{}: {} -> {}\n", t.name, t.writers.empty() ? std::string(t.readers[0].second->type().name) : t.type_name,
                     t.routed ? " (routed)" : "", w.empty() ? "(none)" : fmt::format("{}", fmt::join(w, ", ")),
                     r.empty() ? "(not read)" : fmt::format("{}", fmt::join(r, ", ")));
  }
  return s;
}

void PortGraph::bind_readers(GraphTopic& t, const OutputBase* src) {
  t.current = src;
  for (auto& [i, in] : t.readers) in->bind(src);
}

const OutputBase* PortGraph::routed_writer(const GraphTopic& t, std::optional<std::size_t> active) {
  const OutputBase* src = nullptr;
  for (auto& [i, o] : t.writers)
    if (active && i == *active) src = o;  // (the last, should a controller write a topic twice)
  return src;
}

void PortGraph::bind(std::optional<std::size_t> active) {
  for (auto& t : topics_) {
    if (t.host_writer)
      bind_readers(t, t.host_writer);
    else if (t.routed)
      bind_readers(t, routed_writer(t, active));
    else if (!t.writers.empty())
      bind_readers(t, t.writers.front().second);
  }
}

void PortGraph::route(std::optional<std::size_t> active) {
  for (auto& t : topics_)
    if (t.routed)
      bind_readers(t, routed_writer(t, active));
    else if (!t.host_writer && !t.writers.empty() && t.current != t.writers.front().second)
      bind_readers(t, t.writers.front().second);  // route_topic's override of a plugin's topic ends
}

bool PortGraph::route_topic(const std::string& topic, const OutputBase* src) {
  for (auto& t : topics_)
    if (t.name == topic && (t.routed || (!t.host_writer && !t.writers.empty()))) {
      bind_readers(t, src);
      return true;
    }
  return false;
}

}  // namespace tern::core
