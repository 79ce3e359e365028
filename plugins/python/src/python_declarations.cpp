// A Python plugin's declarations: the script's class, its ports and its parameters, read from the
// class attributes `inputs`, `outputs` and `params` (python_plugin.hpp), declared to the host
// as any plugin's are.
#include <cctype>
#include <filesystem>
#include <limits>
#include <optional>
#include <variant>

#include <fmt/format.h>

#include "python_plugin.hpp"

namespace tern::python_plugin {

namespace {

// The instance's own module name: two instances of one script share no globals.
std::string module_name_for(const std::string& instance) {
  std::string out = "tern_python_plugin_";
  for (char c : instance) out += (std::isalnum(static_cast<unsigned char>(c)) != 0) ? c : '_';
  return out;
}

std::string message_type_names() {
  std::string out;
#define TERN_PYTHON_TYPE_NAME_(T) out += (out.empty() ? "" : ", ") + std::string(T::type_name.substr(5));
  TERN_STANDARD_MESSAGES(TERN_PYTHON_TYPE_NAME_)
#undef TERN_PYTHON_TYPE_NAME_
  return out;
}

bool is_method(PyObject* cls, const std::string& name) {
  if (PyObject_HasAttrString(cls, name.c_str()) == 0) return false;
  Ref attr = Ref::take(PyObject_GetAttrString(cls, name.c_str()));
  return PyCallable_Check(attr.get()) != 0;
}

}  // namespace

void PythonPlugin::load_class() {
  const std::filesystem::path script = script_();
  if (!std::filesystem::is_regular_file(script)) fail("no such file");
  module_name_ = module_name_for(context().instance_name());
  Ref sys_path = Ref::borrow(PySys_GetObject("path"));
  Ref dir = Ref::take(PyUnicode_FromString(script.parent_path().c_str()));
  if (sys_path && PySequence_Contains(sys_path.get(), dir.get()) == 0 && PyList_Insert(sys_path.get(), 0, dir.get()) != 0)
    throw_python_error();
  try {
    Ref util = Ref::take(PyImport_ImportModule("importlib.util"));
    Ref spec = Ref::take(PyObject_CallMethod(util.get(), "spec_from_file_location", "ss", module_name_.c_str(), script.c_str()));
    module_ = Ref::take(PyObject_CallMethod(util.get(), "module_from_spec", "O", spec.get()));
    if (PyDict_SetItemString(PyImport_GetModuleDict(), module_name_.c_str(), module_.get()) != 0) throw_python_error();
    Ref loader = Ref::take(PyObject_GetAttrString(spec.get(), "loader"));
    Ref done = Ref::take(PyObject_CallMethod(loader.get(), "exec_module", "O", module_.get()));
  } catch (const PythonError& e) {
    fail(e.what());
  }
  std::string name = class_name_();
  if (name.empty()) {  // the one class of the script's own that has a step method
    Ref items = Ref::take(PyDict_Items(PyModule_GetDict(module_.get())));
    std::vector<std::string> found;
    for (Py_ssize_t k = 0; k < PyList_GET_SIZE(items.get()); ++k) {
      PyObject* value = PyTuple_GET_ITEM(PyList_GET_ITEM(items.get(), k), 1);
      if (!PyType_Check(value) || PyObject_HasAttrString(value, "step") == 0) continue;
      Ref owner = Ref::take(PyObject_GetAttrString(value, "__module__"));
      if (text_of(owner.get()) == module_name_) found.push_back(text_of(PyTuple_GET_ITEM(PyList_GET_ITEM(items.get(), k), 0)));
    }
    if (found.size() != 1)
      fail(fmt::format("params.class is not set and the script defines {} classes with a step method{}: name one", found.size(),
                       found.empty() ? "" : " (" + fmt::format("{}", fmt::join(found, ", ")) + ")"));
    name = found.front();
  }
  if (PyObject_HasAttrString(module_.get(), name.c_str()) == 0) fail(fmt::format("no class '{}' in the script", name));
  cls_ = Ref::take(PyObject_GetAttrString(module_.get(), name.c_str()));
  if (!PyType_Check(cls_.get())) fail(fmt::format("'{}' is not a class", name));
  if (PyObject_HasAttrString(cls_.get(), "step") == 0) fail(fmt::format("class {} has no step(self, now, inputs) method", name));
}

void PythonPlugin::declare_ports(const char* attribute, bool input) {
  if (PyObject_HasAttrString(cls_.get(), attribute) == 0) return;
  Ref ports = Ref::take(PyObject_GetAttrString(cls_.get(), attribute));
  if (!PyDict_Check(ports.get())) fail(fmt::format("`{}` is a dict {{port: message type}}, not {}", attribute, text_of(ports.get())));
  PyObject *key = nullptr, *spec = nullptr;
  Py_ssize_t pos = 0;
  while (PyDict_Next(ports.get(), &pos, &key, &spec)) declare_port(text_of(key), spec, input);
}

void PythonPlugin::declare_port(const std::string& port, PyObject* spec, bool input) {
  std::string type, description;
  Need need = Need::required;
  if (PyUnicode_Check(spec)) {
    type = text_of(spec);
  } else if (PyDict_Check(spec) && PyDict_GetItemString(spec, "type") != nullptr) {
    type = text_of(PyDict_GetItemString(spec, "type"));
    if (PyObject* d = PyDict_GetItemString(spec, "description")) description = text_of(d);
    if (PyObject* n = PyDict_GetItemString(spec, "need")) {
      const std::string how = text_of(n);
      if (how != "required" && how != "optional") fail(fmt::format("port '{}': need is 'required' or 'optional', not '{}'", port, how));
      need = how == "optional" ? Need::optional : Need::required;
    }
  } else {
    fail(fmt::format("port '{}': a message type (\"State\") or {{\"type\": ..., \"need\": ..., \"description\": ...}}, not {}", port,
                     text_of(spec)));
  }
  const std::string wanted = type.rfind("tern/", 0) == 0 ? type : "tern/" + type;
  bool found = false;
#define TERN_PYTHON_PORT_(T)                 \
  if (!found && T::type_name == wanted) {    \
    found = true;                            \
    if (input)                               \
      add_input<T>(port, description, need); \
    else                                     \
      add_output<T>(port, description);      \
  }
  TERN_STANDARD_MESSAGES(TERN_PYTHON_PORT_)
#undef TERN_PYTHON_PORT_
  if (!found) fail(fmt::format("port '{}': no message type '{}' (the types: {})", port, type, message_type_names()));
}

template <class T>
void PythonPlugin::add_input(const std::string& port, const std::string& description, Need need) {
  auto p = std::make_unique<Input<T>>();
  declare(*p, port, description, need);
  inputs_py_.push_back({p.get(), std::make_shared<const MessageObjects>(std::string(T::type_name), reflect::layout<T>()),
                        Ref::take(PyUnicode_FromString(port.c_str())), 0, Ref::borrow(Py_None)});
  owned_ports_.push_back(std::move(p));
}

template <class T>
void PythonPlugin::add_output(const std::string& port, const std::string& description) {
  auto p = std::make_unique<Output<T>>();
  declare(*p, port, description);
  auto scratch = std::make_shared<T>();
  Output<T>* raw = p.get();
  outputs_py_.push_back({p.get(), std::make_shared<const MessageObjects>(std::string(T::type_name), reflect::layout<T>()),
                         [scratch] {
                           *scratch = T{};
                           return static_cast<void*>(scratch.get());
                         },
                         [raw, scratch] { raw->publish(*scratch); }});
  owned_ports_.push_back(std::move(p));
}

// params = {name: default} or {name: (default, unit, min, max, description)} (a prefix of it).
void PythonPlugin::declare_params() {
  if (PyObject_HasAttrString(cls_.get(), "params") == 0) return;
  Ref params = Ref::take(PyObject_GetAttrString(cls_.get(), "params"));
  if (!PyDict_Check(params.get()))
    fail("`params` is a dict {name: default or (default, unit, min, max, description)}, not " + text_of(params.get()));
  PyObject *key = nullptr, *spec = nullptr;
  Py_ssize_t pos = 0;
  while (PyDict_Next(params.get(), &pos, &key, &spec)) {
    const std::string name = text_of(key);
    if (name == "script" || name == "class" || name == "seed" || name == "instance" || name == "log" || is_method(cls_.get(), name))
      fail(fmt::format("parameter '{}' would hide the plugin's own '{}': choose another name", name, name));
    const bool tuple = PyTuple_Check(spec) != 0;
    const Py_ssize_t n = tuple ? PyTuple_GET_SIZE(spec) : 1;
    if (n < 1 || n > 5) fail(fmt::format("parameter '{}': (default, unit, min, max, description), not {}", name, text_of(spec)));
    PyObject* value = tuple ? PyTuple_GET_ITEM(spec, 0) : spec;
    ParamSpec ps;
    if (n > 1) ps.unit = text_of(PyTuple_GET_ITEM(spec, 1));
    const auto bound = [&](Py_ssize_t k, double fallback) {
      if (n <= k || PyTuple_GET_ITEM(spec, k) == Py_None) return fallback;
      const std::optional<double> x = python::number(PyTuple_GET_ITEM(spec, k));
      if (!x) fail(fmt::format("parameter '{}': its bound {} is not a number", name, text_of(PyTuple_GET_ITEM(spec, k))));
      return *x;
    };
    ps.min = bound(2, -std::numeric_limits<double>::infinity());
    ps.max = bound(3, std::numeric_limits<double>::infinity());
    if (n > 4) ps.description = text_of(PyTuple_GET_ITEM(spec, 4));
    ParamValue default_value;
    try {
      default_value = python::param_value(value, fmt::format("parameter '{}': a default", name));
    } catch (const python::ConversionError& e) {
      fail(e.what());
    }
    std::visit([&](auto& v) { add_param(name, std::move(v), ps); }, default_value);
  }
}

template <class T>
void PythonPlugin::add_param(const std::string& name, T default_value, ParamSpec spec) {
  auto p = std::make_unique<Param<T>>();
  declare(*p, name, std::move(default_value), std::move(spec));
  p->on_change([this](const T&) { params_changed_ = true; });
  params_py_.push_back({p.get(), Ref::take(PyUnicode_FromString(name.c_str()))});
  owned_params_.push_back(std::move(p));
}

void PythonPlugin::push_params() {
  for (const auto& p : params_py_) {
    const python::py::object value = python::param_object(p.param->value());
    if (PyObject_SetAttr(instance_.get(), p.name.get(), value.ptr()) != 0) throw_python_error();
  }
}

}  // namespace tern::python_plugin
