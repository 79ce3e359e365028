// plugins/python/src/interpreter.hpp: the CPython interpreter a Python plugin runs in, and the
// few handles the plugin needs around the C API (https://docs.python.org/3/c-api/).
//
// One interpreter per process, started by the first Python plugin configured in it, or found
// running when the host itself is driven from Python (`import tern`, docs/python.md). Started:
//   - without Python's signal handlers (the host's SIGINT/SIGTERM handling stays the host's),
//   - with hash seed 0 (the iteration order of a set of strings is the same from run to run),
//   - with its library made global (RTLD_GLOBAL), so that extension modules such as numpy find
//     the interpreter's symbols although the host opened this plugin with RTLD_LOCAL, and never
//     unloaded (RTLD_NODELETE): a hot-swap unloads the plugin, never the interpreter.
// It is never finalised (numpy and other extensions do not survive a second initialisation).
//
// No Python object created by the plugin carries a pointer into this shared object's code, so the
// host can unload it (hot-swap) with the interpreter alive: the plain C API here, and the SDK's
// conversion of messages and parameters (tern/python/conversion.hpp), which uses pybind11's object
// wrappers only and never makes pybind11's internals.
#pragma once

#include <Python.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace tern::python_plugin {

/// A Python exception as a C++ one: what() is one line, "<file>:<line> in <function>:
/// <ExceptionType>: <message>" (the innermost frame of the traceback).
struct PythonError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Starts the interpreter once per process (see above); throws std::runtime_error when it
/// cannot start. Then makes the module `tern_sdk`: the SDK's constants for scripts, from the
/// same declarations the C++ uses (tern/math.hpp, tern/atmosphere.hpp), as Python floats:
///   GRAVITY (kGravity, the book's g, m/s^2), STANDARD_GRAVITY (kStandardGravity, m/s^2),
///   RAD_PER_DEG, DEG_PER_RAD, ISA_SEA_LEVEL_PRESSURE (Pa), ISA_SEA_LEVEL_DENSITY (kg/m^3).
/// Plain values only: nothing in it points into this shared object.
void ensure_interpreter();

/// Holds the GIL for a scope, on any thread (PyGILState_Ensure).
class Gil {
 public:
  Gil() : state_(PyGILState_Ensure()) {}
  ~Gil() { PyGILState_Release(state_); }
  Gil(const Gil&) = delete;
  Gil& operator=(const Gil&) = delete;

 private:
  PyGILState_STATE state_;
};

/// An owned reference (Py_XDECREF when it goes). Take the GIL before making or dropping one.
class Ref {
 public:
  Ref() = default;
  /// Takes ownership of a new reference; nullptr (a failed C API call) throws the pending
  /// Python exception as PythonError.
  static Ref take(PyObject* p);
  /// Adds a reference to a borrowed one.
  static Ref borrow(PyObject* p) {
    Py_XINCREF(p);
    return Ref(p);
  }
  Ref(Ref&& o) noexcept : p_(std::exchange(o.p_, nullptr)) {}
  Ref& operator=(Ref&& o) noexcept {
    if (this != &o) {
      Py_XDECREF(p_);
      p_ = std::exchange(o.p_, nullptr);
    }
    return *this;
  }
  Ref(const Ref&) = delete;
  Ref& operator=(const Ref&) = delete;
  ~Ref() { Py_XDECREF(p_); }
  PyObject* get() const { return p_; }
  explicit operator bool() const { return p_ != nullptr; }
  void reset() { *this = Ref(); }

 private:
  explicit Ref(PyObject* p) : p_(p) {}
  PyObject* p_ = nullptr;
};

/// The pending Python exception as PythonError (cleared). Call only when one is set.
[[noreturn]] void throw_python_error();

/// str(o) as UTF-8 ("<unprintable>" if even that fails).
std::string text_of(PyObject* o);

/// o.name(*args) when o has such an attribute (a new reference), else an empty Ref.
Ref call_if_defined(PyObject* o, const char* name, PyObject* args = nullptr);

}  // namespace tern::python_plugin
