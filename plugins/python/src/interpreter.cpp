// The embedded interpreter and its handles. See interpreter.hpp.
#include "interpreter.hpp"

#include <dlfcn.h>

#include <cstring>
#include <mutex>

#include <fmt/format.h>

#include "tern/atmosphere.hpp"
#include "tern/math.hpp"

namespace tern::python_plugin {

namespace {

// The interpreter's library made global and resident (interpreter.hpp): found from one of its
// own functions, so that it is the library this plugin was linked against.
void make_libpython_global() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&Py_InitializeFromConfig), &info) == 0 || info.dli_fname == nullptr) return;
  // a process linked statically against Python (no separate library): nothing to promote
  dlopen(info.dli_fname, RTLD_NOW | RTLD_GLOBAL | RTLD_NODELETE | RTLD_NOLOAD);
}

void start() {
  make_libpython_global();
  if (Py_IsInitialized()) return;  // the host runs inside Python (import tern)
  PyConfig config;
  PyConfig_InitPythonConfig(&config);
  config.install_signal_handlers = 0;
  config.use_hash_seed = 1;
  config.hash_seed = 0;
  config.parse_argv = 0;
  const PyStatus status = Py_InitializeFromConfig(&config);
  PyConfig_Clear(&config);
  if (PyStatus_Exception(status))
    throw std::runtime_error(
        fmt::format("the Python interpreter did not start: {}", status.err_msg ? status.err_msg : "(no reason given)"));
  PyEval_SaveThread();  // the GIL is taken by each call (Gil), on whatever thread flies
}

// "<file>:<line> in <function>" of the innermost frame of `tb`, "" without one.
std::string innermost_frame(PyObject* tb) {
  if (tb == nullptr || tb == Py_None) return {};
  Ref last = Ref::borrow(tb);
  for (;;) {
    Ref next = Ref::take(PyObject_GetAttrString(last.get(), "tb_next"));
    if (next.get() == Py_None) break;
    last = std::move(next);
  }
  Ref line = Ref::take(PyObject_GetAttrString(last.get(), "tb_lineno"));
  Ref frame = Ref::take(PyObject_GetAttrString(last.get(), "tb_frame"));
  Ref code = Ref::take(PyObject_GetAttrString(frame.get(), "f_code"));
  Ref file = Ref::take(PyObject_GetAttrString(code.get(), "co_filename"));
  Ref function = Ref::take(PyObject_GetAttrString(code.get(), "co_name"));
  return fmt::format("{}:{} in {}", text_of(file.get()), PyLong_AsLong(line.get()), text_of(function.get()));
}

// The module `tern_sdk` (interpreter.hpp), made once per interpreter.
void make_sdk_module() {
  Gil gil;
  PyObject* modules = PyImport_GetModuleDict();
  if (PyDict_GetItemString(modules, "tern_sdk") != nullptr) return;  // a plugin loaded before this one made it
  Ref m = Ref::take(PyModule_New("tern_sdk"));
  const std::pair<const char*, double> constants[] = {
      {"GRAVITY", kGravity},       {"STANDARD_GRAVITY", kStandardGravity},           {"RAD_PER_DEG", kRadPerDeg},
      {"DEG_PER_RAD", kDegPerRad}, {"ISA_SEA_LEVEL_PRESSURE", kIsaSeaLevelPressure}, {"ISA_SEA_LEVEL_DENSITY", kIsaSeaLevelDensity}};
  for (const auto& [name, value] : constants)
    if (PyModule_AddObject(m.get(), name, PyFloat_FromDouble(value)) != 0) throw_python_error();
  if (PyDict_SetItemString(modules, "tern_sdk", m.get()) != 0) throw_python_error();
}

}  // namespace

void ensure_interpreter() {
  static std::once_flag once;
  std::call_once(once, [] {
    start();
    make_sdk_module();
  });
}

Ref Ref::take(PyObject* p) {
  if (p == nullptr) throw_python_error();
  return Ref(p);
}

std::string text_of(PyObject* o) {
  if (o == nullptr) return "<null>";
  PyObject* s = PyObject_Str(o);
  if (s == nullptr) {
    PyErr_Clear();
    return "<unprintable>";
  }
  const char* utf8 = PyUnicode_AsUTF8(s);
  std::string out = utf8 != nullptr ? utf8 : "<unprintable>";
  if (utf8 == nullptr) PyErr_Clear();
  Py_DECREF(s);
  return out;
}

void throw_python_error() {
  PyObject *type = nullptr, *value = nullptr, *tb = nullptr;
  PyErr_Fetch(&type, &value, &tb);
  if (type == nullptr) throw PythonError("a Python call failed without an exception");
  PyErr_NormalizeException(&type, &value, &tb);
  Ref type_ref = Ref::borrow(type), value_ref = Ref::borrow(value), tb_ref = Ref::borrow(tb);
  Py_XDECREF(type);
  Py_XDECREF(value);
  Py_XDECREF(tb);
  std::string where;
  try {
    where = innermost_frame(tb_ref.get());
  } catch (const PythonError&) {
    PyErr_Clear();
  }
  const char* name = PyExceptionClass_Check(type_ref.get()) ? PyExceptionClass_Name(type_ref.get()) : "exception";
  if (const char* dot = std::strrchr(name, '.')) name = dot + 1;
  const std::string message = text_of(value_ref.get());
  std::string line = where.empty() ? "" : where + ": ";
  line += message.empty() ? std::string(name) : fmt::format("{}: {}", name, message);
  throw PythonError(line);
}

Ref call_if_defined(PyObject* o, const char* name, PyObject* args) {
  if (PyObject_HasAttrString(o, name) == 0) return {};
  Ref f = Ref::take(PyObject_GetAttrString(o, name));
  return Ref::take(args != nullptr ? PyObject_CallObject(f.get(), args) : PyObject_CallNoArgs(f.get()));
}

}  // namespace tern::python_plugin
