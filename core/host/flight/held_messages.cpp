#include "flight/held_messages.hpp"

#include <algorithm>
#include <cstring>

#include <fmt/format.h>

#include "config/error.hpp"
#include "graph/message_columns.hpp"

namespace tern::core {

void HeldMessages::hold(const std::string& topic, const MsgType& type, const std::vector<std::pair<std::string, double>>& fields) {
  const std::vector<reflect::Column> columns = type.columns();
  Held h{topic, {}, nullptr, 0, std::vector<std::byte>(type.size)};
  for (const auto& [name, value] : fields) {
    const reflect::Column* c = find_column(columns, name);
    if (c == nullptr)
      throw ConfigError(fmt::format("topic '{}' ({}): no field '{}'; its fields: {}", topic, type.name, name, column_names(columns)));
    if (const std::string problem = column_problem(*c, value); !problem.empty())
      throw ConfigError(fmt::format("topic '{}' ({}): {}", topic, type.name, problem));
    h.fields.push_back({*c, value});
  }
  release(topic);
  held_.push_back(std::move(h));
}

bool HeldMessages::release(const std::string& topic) {
  return std::erase_if(held_, [&](const Held& h) { return h.topic == topic; }) > 0;
}

void HeldMessages::new_flight() {
  for (auto& h : held_) h.applied_to = nullptr;
}

void HeldMessages::apply(const PortGraph& graph) {
  for (auto& h : held_) {
    const GraphTopic* t = graph.find(h.topic);
    OutputBase* out = nullptr;
    if (t != nullptr)
      for (const auto& [node, writer] : t->writers)
        if (writer == t->current) out = writer;
    if (out == nullptr || out->sequence() == 0 || (out == h.applied_to && out->sequence() == h.applied_seq)) continue;
    std::memcpy(h.scratch.data(), out->data(), h.scratch.size());
    for (const auto& f : h.fields) set_column_value(f.column, h.scratch.data(), f.value);
    out->publish_copy(h.scratch.data(), out->sequence());
    h.applied_to = out;
    h.applied_seq = out->sequence();
  }
}

}  // namespace tern::core
