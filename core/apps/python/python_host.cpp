#include "python/python_host.hpp"

#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "commands/mission_check.hpp"
#include "config/error.hpp"
#include "graph/message_columns.hpp"
#include "tern/msg/sensors.hpp"

namespace tern::core::python {

namespace {

/// {field: number} as (field, value) pairs for `topic`; a key that is not a str or a value that
/// is not a real number (tern/python/conversion.hpp) throws ConfigError naming the topic and the
/// field. The fields' names and ranges are checked where they are held (held_messages.hpp).
std::vector<std::pair<std::string, double>> message_fields(const std::string& topic, const py::dict& fields) {
  std::vector<std::pair<std::string, double>> out;
  for (const auto& [key, value] : fields) {
    if (!py::isinstance<py::str>(key))
      throw ConfigError(fmt::format("topic '{}': field name {} is not a str", topic, tern::python::repr_of(key)));
    const std::string name = key.cast<std::string>();
    const std::optional<double> x = tern::python::number(value);
    if (!x) throw ConfigError(fmt::format("topic '{}': field '{}': {} is not a number", topic, name, tern::python::repr_of(value)));
    out.emplace_back(name, *x);
  }
  return out;
}

}  // namespace

HostPreparation preparation(const PythonFlightOptions& o) {
  HostPreparation p;
  p.overrides.sets = o.sets;
  p.log_level = o.log_level;
  p.log_format = o.log_format;
  return p;
}

HostOptions host_options(const PythonFlightOptions& o) {
  HostOptions h;
  h.seed = o.seed;
  h.duration = o.duration;
  if (o.log_dir) h.log_dir = fs::path(*o.log_dir);
  h.quiet = o.quiet;
  return h;
}

PythonHost::PythonHost(std::string config_file, PythonFlightOptions options)
    : config_file_(std::move(config_file)), options_(std::move(options)) {
  PreparedMission m = prepare_mission(config_file_, preparation(options_));
  const MissionReport r = check_missions(m.config);  // refused before anything flies, as tern fly does
  if (!r.errors.empty()) throw ConfigError(fmt::format("{}: the mission check refused it: {}", config_file_, fmt::join(r.errors, "; ")));
  build();
}

PythonHost::~PythonHost() {
  if (running_) host_->end_flight("aborted");
}

void PythonHost::build() {
  host_.reset();  // its libraries unloaded before the new host loads them
  host_ = std::make_unique<Host>(prepare_mission(config_file_, preparation(options_)).config, host_options(options_));
  host_->build();
  for (const auto& [instance, so] : swaps_) host_->swap(instance, so);
  seed_ = options_.seed.value_or(host_->config().seed);
}

void PythonHost::begin() {
  end_reason_.clear();
  running_ = true;
  if (!host_->begin_flight()) end();
}

void PythonHost::reset(std::optional<std::uint64_t> seed) {
  if (running_) end();
  if (seed && *seed != seed_) {
    options_.seed = *seed;
    if (host_->reseed(*seed))
      seed_ = *seed;  // the libraries, instances and port graph stay
    else
      build();
  }
  begin();
}

bool PythonHost::step(std::int64_t ticks) {
  if (!running_ && end_reason_.empty()) throw ConfigError("Host.step: no flight yet: call reset() first");
  py::gil_scoped_release unlocked;
  for (std::int64_t i = 0; i < ticks && running_; ++i)
    if (!host_->tick()) end();
  return running_;
}

bool PythonHost::step_until(double t_s) {
  if (!running_ && end_reason_.empty()) throw ConfigError("Host.step_until: no flight yet: call reset() first");
  const Nanos t = from_seconds(t_s);
  py::gil_scoped_release unlocked;
  while (running_ && host_->now() < t)
    if (!host_->tick()) end();
  return running_;
}

double PythonHost::time() const { return to_seconds(running_ ? host_->now() : ended_at_); }

double PythonHost::base_period() const { return to_seconds(host_->base_period()); }

std::vector<std::string> PythonHost::topics() const {
  std::vector<std::string> out;
  for (const auto& t : host_->topics()) out.push_back(t.name);
  return out;
}

py::list PythonHost::handovers() const {
  py::list out;
  for (const Handover& h : host_->handovers()) {
    py::dict d;
    d["t"] = to_seconds(h.t);
    d["from"] = h.from;
    d["to"] = h.to;
    d["reason"] = h.reason;
    out.append(d);
  }
  return out;
}

std::string PythonHost::topic_list() const { return fmt::format("{}", fmt::join(topics(), ", ")); }

const tern::python::MessageColumns& PythonHost::columns_of(const MsgType& type) const {
  auto it = columns_.find(type.name);
  if (it == columns_.end()) it = columns_.emplace(std::string(type.name), tern::python::MessageColumns(type.columns())).first;
  return it->second;
}

const OutputBase& PythonHost::topic_output(const std::string& topic) const {
  const OutputBase* o = host_->topic_source(topic);
  if (o == nullptr)
    throw ConfigError(fmt::format("Host.read: no topic '{}' in mission '{}'; its topics: {}", topic, host_->config().name, topic_list()));
  return *o;
}

const reflect::Column& PythonHost::field_column(const std::string& topic, const OutputBase& output, const std::string& field) const {
  const std::vector<reflect::Column>& columns = columns_of(output.type()).columns();
  const reflect::Column* c = find_column(columns, field);
  if (c == nullptr)
    throw ConfigError(
        fmt::format("Host.read: topic '{}' ({}): no field '{}'; its fields: {}", topic, output.type().name, field, column_names(columns)));
  return *c;
}

py::object PythonHost::read(const std::string& topic, const std::optional<std::vector<std::string>>& fields) const {
  const OutputBase& o = topic_output(topic);
  if (!fields) return o.sequence() == 0 ? py::none() : py::object(columns_of(o.type()).to_dict(o.data()));
  py::tuple out(fields->size());
  for (std::size_t i = 0; i < fields->size(); ++i) {
    const reflect::Column& c = field_column(topic, o, (*fields)[i]);
    out[i] = py::float_(o.sequence() == 0 ? 0.0 : column_value(c, o.data()));
  }
  return out;
}

void PythonHost::write(const std::string& topic, const py::dict& fields) { write_fields(topic, message_fields(topic, fields)); }

void PythonHost::write_fields(const std::string& topic, const std::vector<std::pair<std::string, double>>& values) {
  if (topic != "pilot" || !host_->takes_pilot()) {
    host_->hold_message(topic, values);
    return;
  }
  msg::Rc rc;
  const auto& columns = columns_of(msg_type_v<msg::Rc>).columns();
  for (const auto& [name, v] : values) {
    const reflect::Column* c = find_column(columns, name);
    if (c == nullptr) throw ConfigError(fmt::format("topic 'pilot' (tern/Rc): no field '{}'; its fields: {}", name, column_names(columns)));
    if (const std::string problem = column_problem(*c, v); !problem.empty()) throw ConfigError("topic 'pilot' (tern/Rc): " + problem);
    set_column_value(*c, &rc, v);
  }
  host_->set_pilot(rc);
}

py::object PythonHost::get_param(const std::string& name) const {
  for (const auto& [qualified, p] : host_->parameters())
    if (qualified == name) return tern::python::param_object(host_->param_value(*p));
  throw ConfigError(
      fmt::format("Host.get_param: no parameter '{}' in mission '{}' (tern params CONFIG lists them)", name, host_->config().name));
}

void PythonHost::set_param(const std::string& name, const py::handle& value) {
  ParamValue v;
  try {
    v = tern::python::param_value(value, fmt::format("parameter '{}': a value", name));
  } catch (const tern::python::ConversionError& e) {
    throw ConfigError(e.what());
  }
  host_->request_param(name, std::move(v), "python");
}

void PythonHost::swap(const std::string& instance, const std::string& so) {
  if (running_) throw ConfigError(fmt::format("Host.swap('{}'): a flight is running: end() it first", instance));
  host_->swap(instance, so);
  swaps_.emplace_back(instance, so);
}

std::string PythonHost::end() {
  if (!running_) return last_run_dir_;
  ended_at_ = host_->now();
  const FlightResult r = host_->end_flight("aborted");
  running_ = false;
  end_reason_ = r.end_reason;
  last_run_dir_ = r.run_dir.string();
  return last_run_dir_;
}

}  // namespace tern::core::python
