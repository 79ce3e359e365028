// sdk/python/include/tern/python/conversion.hpp: tern's messages and parameters as Python objects
// and back: the one conversion for both places Python meets tern, a plugin written in Python
// (plugins/python: its messages as objects with attributes) and tern.Host (core/apps/python: its
// messages as dicts).
//
// Messages go by their log columns (tern/reflect.hpp layout<T>(): "phi", "p_n", "quat_w",
// "aux_0" ...), the names the flight log and `tern.Run` use: a column is a bool for a boolean
// field, an int for an integer one (exact: a stamp in ns), a float otherwise (SI units, the
// log's). A parameter value (tern/param.hpp ParamValue) is a bool, int, float, str or list of floats.
//
// Only pybind11's object wrappers are used (py::object, py::dict, the casts of numbers, strings
// and lists): nothing here registers a class or a function with pybind11, so nothing makes
// pybind11's internals (a record kept in the interpreter, with pointers into the library that
// made it). A Python plugin links this library and is unloaded with the interpreter alive (a hot
// swap): it must never make them. PYBIND11_SIMPLE_GIL_MANAGEMENT, set for every user of the
// library (CMakeLists.txt), keeps pybind11's GIL guards (which py::error_already_set takes) off
// them too. Every call here is made with the GIL held; a MessageColumns is destroyed with it held.
#pragma once

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <pybind11/pybind11.h>

#include "tern/param.hpp"
#include "tern/reflect.hpp"

namespace tern::python {

namespace py = pybind11;

/// A Python value that does not convert: one line naming what it was for and the value.
struct ConversionError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

/// Column `c` of the message at `msg` as a Python bool, int or float (see above).
py::object column_object(const reflect::Column& c, const void* msg);

/// One message type's log columns, with their names as Python strings made once.
class MessageColumns {
 public:
  explicit MessageColumns(std::vector<reflect::Column> columns);
  template <class M>
  static MessageColumns of() {
    return MessageColumns(reflect::layout<M>());
  }

  const std::vector<reflect::Column>& columns() const { return columns_; }
  /// The message at `msg` as {column: value}, in the columns' order.
  py::dict to_dict(const void* msg) const;

 private:
  std::vector<reflect::Column> columns_;
  std::vector<py::str> keys_;  ///< interned, in columns_' order
};

/// A real number from Python: a bool (0 or 1), an int, a float or a numpy scalar; nullopt for
/// anything else (a str, bytes, a complex number, None, a list ...).
std::optional<double> number(py::handle value);

/// repr(value), for error lines.
std::string repr_of(py::handle value);

/// A parameter value as a Python object: bool, int, float, str or a list of floats.
py::object param_object(const ParamValue& value);

/// A Python value as a parameter value: a bool, int, float or str as itself, a numpy scalar as a
/// float, a sequence of numbers (list, tuple, numpy array) as a list of floats. Anything else
/// throws ConversionError, `subject` naming what it was for ("parameter 'k': a default"):
///   "<subject> of bool, int, float, str or a list of numbers, not <repr>"
///   "<subject> <repr>: element <i> is not a number"
ParamValue param_value(py::handle value, std::string_view subject);

}  // namespace tern::python
