// A plugin written in Python: its life. See python_plugin.hpp; the declarations are read in
// python_declarations.cpp.
#include "python_plugin.hpp"

#include <algorithm>
#include <optional>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace tern::python_plugin {

PythonPlugin::~PythonPlugin() {
  if (!Py_IsInitialized() || !module_) return;
  Gil gil;  // every Python object this plugin holds goes while the GIL is held
  inputs_py_.clear();
  outputs_py_.clear();
  params_py_.clear();
  instance_.reset();
  logger_.reset();
  log_queue_.reset();
  cls_.reset();
  module_.reset();
  if (PyObject* modules = PyImport_GetModuleDict(); PyDict_DelItemString(modules, module_name_.c_str()) != 0) PyErr_Clear();
}

void PythonPlugin::configure() {
  ParamSpec script_spec;
  script_spec.description = "the Python file that defines the plugin's class (relative to the file that sets it)";
  declare(script_, "script", "", script_spec.as_path().start_only());
  ParamSpec class_spec;
  class_spec.description = "the class in the script ('' when the script defines exactly one class with a step method)";
  declare(class_name_, "class", "", class_spec.start_only());
  if (script_().empty()) {
    if (context().describing()) return;  // `tern plugins`: the ports and parameters come from a script
    fail("params.script is not set: name the Python file that defines the plugin's class");
  }
  ensure_interpreter();
  Gil gil;
  load_class();
  declare_ports("inputs", true);
  declare_ports("outputs", false);
  declare_params();
  Ref queue_module = Ref::take(PyImport_ImportModule("queue"));
  log_queue_ = Ref::take(PyObject_CallMethod(queue_module.get(), "SimpleQueue", nullptr));
  Ref logging = Ref::take(PyImport_ImportModule("logging"));
  Ref handlers = Ref::take(PyImport_ImportModule("logging.handlers"));
  // an unregistered logger of its own: two hosts in one Python process keep their lines apart
  logger_ = Ref::take(PyObject_CallMethod(logging.get(), "Logger", "s", context().instance_name().c_str()));
  Ref handler = Ref::take(PyObject_CallMethod(handlers.get(), "QueueHandler", "O", log_queue_.get()));
  Ref added = Ref::take(PyObject_CallMethod(logger_.get(), "addHandler", "O", handler.get()));
  if (PyObject_SetAttrString(logger_.get(), "propagate", Py_False) != 0) throw_python_error();
}

void PythonPlugin::start() {
  Gil gil;
  new_instance();
  call("start");
}

void PythonPlugin::step(Nanos now) {
  Gil gil;
  if (params_changed_.exchange(false)) push_params();
  Ref inputs = inputs_dict();
  Ref args = Ref::take(Py_BuildValue("(LO)", static_cast<long long>(now), inputs.get()));
  Ref out = call("step", args.get());
  if (out && out.get() != Py_None) publish(out.get(), now);
}

void PythonPlugin::reset() {
  if (!module_) return;  // described only (no script): nothing of Python's was made
  Gil gil;
  instance_.reset();
  for (auto& in : inputs_py_) {
    in.converted = 0;
    in.message = Ref::borrow(Py_None);
  }
}

void PythonPlugin::take_over(const msg::Actuators& last_command) {
  Gil gil;
  if (instance_ && PyObject_HasAttrString(instance_.get(), "take_over") != 0) {
    const MessageObjects columns(std::string(msg::Actuators::type_name), reflect::layout<msg::Actuators>());
    Ref last = columns.to_python(&last_command);
    Ref args = Ref::take(PyTuple_Pack(1, last.get()));
    call("take_over", args.get());
    return;
  }
  reset();
  new_instance();
  call("start");
}

void PythonPlugin::stop() {
  if (!instance_) return;
  Gil gil;
  call("stop");
}

// A failing summary() loses its own figures only: one error line, and summary.json is written.
std::vector<std::pair<std::string, double>> PythonPlugin::summary() const {
  if (!instance_) return {};
  Gil gil;
  try {
    return summary_figures();
  } catch (const PythonError& e) {
    log().error("summary() failed, its figures are left out: {}", e.what());
    return {};
  }
}

std::vector<std::pair<std::string, double>> PythonPlugin::summary_figures() const {
  Ref figures = call_if_defined(instance_.get(), "summary");
  if (!figures || figures.get() == Py_None) return {};
  if (!PyDict_Check(figures.get())) fail("summary() returns a dict {name: number}, not " + text_of(figures.get()));
  std::vector<std::pair<std::string, double>> out;
  PyObject *key = nullptr, *value = nullptr;
  Py_ssize_t pos = 0;
  while (PyDict_Next(figures.get(), &pos, &key, &value)) {
    const std::optional<double> x = python::number(value);
    if (!x) fail(fmt::format("summary()['{}'] is not a number: {}", text_of(key), text_of(value)));
    out.emplace_back(text_of(key), *x);
  }
  return out;
}

// ---- calls --------------------------------------------------------------------------------

// A fresh object of the class: the parameters, seed, instance name and logger set before
// __init__ runs, so that __init__ can use them.
void PythonPlugin::new_instance() {
  instance_ = Ref::take(PyObject_CallMethod(cls_.get(), "__new__", "O", cls_.get()));
  Ref seed = Ref::take(PyLong_FromUnsignedLongLong(context().seed()));
  Ref name = Ref::take(PyUnicode_FromString(context().instance_name().c_str()));
  if (PyObject_SetAttrString(instance_.get(), "seed", seed.get()) != 0 ||
      PyObject_SetAttrString(instance_.get(), "instance", name.get()) != 0 ||
      PyObject_SetAttrString(instance_.get(), "log", logger_.get()) != 0)
    throw_python_error();
  params_changed_ = false;
  push_params();
  call("__init__");
}

// instance.method(*args) when the class defines it; the log lines it wrote go to the instance's
// log whatever happens.
Ref PythonPlugin::call(const char* method, PyObject* args) {
  Ref out;
  try {
    out = call_if_defined(instance_.get(), method, args);
  } catch (const PythonError&) {
    drain_log();
    throw;
  }
  drain_log();
  return out;
}

Ref PythonPlugin::inputs_dict() {
  Ref inputs = Ref::take(PyDict_New());
  for (auto& in : inputs_py_) {
    if (!in.port->has_value()) {
      in.message = Ref::borrow(Py_None);
    } else if (const std::uint64_t seq = in.port->source()->sequence(); seq != in.converted) {
      in.message = in.columns->to_python(in.port->source()->data());
      in.converted = seq;
    }
    if (PyDict_SetItem(inputs.get(), in.key.get(), in.message.get()) != 0) throw_python_error();
  }
  return inputs;
}

void PythonPlugin::publish(PyObject* outputs, Nanos now) {
  if (!PyDict_Check(outputs)) fail("step() returns None or a dict {output: message}, not " + text_of(outputs));
  PyObject *key = nullptr, *fields = nullptr;
  Py_ssize_t pos = 0;
  while (PyDict_Next(outputs, &pos, &key, &fields)) {
    const std::string port = text_of(key);
    auto it = std::find_if(outputs_py_.begin(), outputs_py_.end(), [&](const OutputSlot& o) { return o.port->name() == port; });
    if (it == outputs_py_.end()) fail(fmt::format("step() returned output '{}', which the class does not declare in `outputs`", port));
    if (fields == Py_None) continue;
    void* message = it->fresh();
    it->columns->from_python(fields, message, now, port);
    it->publish();
  }
}

void PythonPlugin::drain_log() {
  if (!log_queue_) return;
  while (PyObject_IsTrue(Ref::take(PyObject_CallMethod(log_queue_.get(), "empty", nullptr)).get()) == 0) {
    Ref record = Ref::take(PyObject_CallMethod(log_queue_.get(), "get_nowait", nullptr));
    Ref level = Ref::take(PyObject_GetAttrString(record.get(), "levelno"));
    Ref text = Ref::take(PyObject_CallMethod(record.get(), "getMessage", nullptr));
    const long n = PyLong_AsLong(level.get());
    const auto lvl = n >= 40 ? spdlog::level::err : n >= 30 ? spdlog::level::warn : n >= 20 ? spdlog::level::info : spdlog::level::debug;
    log().log(lvl, "{}", text_of(text.get()));
  }
}

void PythonPlugin::fail(const std::string& what) const {
  throw PythonError(fmt::format("{}: {}", script_().empty() ? "python plugin" : script_(), what));
}

}  // namespace tern::python_plugin
