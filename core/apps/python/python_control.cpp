#include "python/python_control.hpp"

#include <fmt/format.h>

#include "config/error.hpp"
#include "python/python_host.hpp"

namespace tern::core::python {

PythonControl::PythonControl(PythonHost& host, std::string topic, std::vector<std::string> fields,
                             std::vector<std::pair<std::string, std::string>> observation)
    : host_(host), topic_(std::move(topic)) {
  if (fields.empty()) throw ConfigError(fmt::format("Host.control('{}'): no action fields", topic_));
  for (auto& f : fields) action_.emplace_back(std::move(f), 0.0);
  for (auto& [t, f] : observation) observation_.push_back(Pair{std::move(t), std::move(f), {}, nullptr});
}

py::tuple PythonControl::operator()(const std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>& action,
                                    std::int64_t ticks) {
  if (!action) {
    host_.release(topic_);
  } else {
    if (static_cast<std::size_t>(action->size()) != action_.size())
      throw ConfigError(fmt::format("Control: an action of {} values for the {} fields of '{}'", action->size(), action_.size(), topic_));
    const double* a = action->data();
    for (std::size_t i = 0; i < action_.size(); ++i) action_[i].second = a[i];
    host_.write_fields(topic_, action_);
  }
  const bool going = host_.step(ticks);
  return py::make_tuple(going, read());
}

py::array_t<double> PythonControl::read() {
  py::array_t<double> out(static_cast<py::ssize_t>(observation_.size()));
  read_into(out.mutable_data());
  return out;
}

// Each pair's column is looked up again only when its topic's producer has another message type
// than the last (a phase's controller of another kind): otherwise it is the one found before.
void PythonControl::read_into(double* out) {
  for (std::size_t i = 0; i < observation_.size(); ++i) {
    Pair& p = observation_[i];
    const OutputBase& o = host_.topic_output(p.topic);
    if (p.column == nullptr || o.type().name != p.type) {
      p.column = &host_.field_column(p.topic, o, p.field);
      p.type = o.type().name;
    }
    out[i] = o.sequence() == 0 ? 0.0 : column_value(*p.column, o.data());
  }
}

}  // namespace tern::core::python
