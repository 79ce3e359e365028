// core/apps/python/python_messages.hpp: tern's messages and parameters as Python objects, by the
// names the flight log uses: a message is a dict {column: value} (graph/message_columns.hpp:
// "delta_a", "p_n", "quat_w" ...), a parameter value a bool, int, float, str or list of floats.
// What cannot be converted throws ConfigError naming the topic or parameter and the field, which
// the module raises as tern.Error (module.cpp).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <pybind11/pybind11.h>

#include "tern/param.hpp"
#include "tern/port.hpp"

namespace tern::core::python {

namespace py = pybind11;

/// The message at `msg` with log columns `columns` as {column: value}: bool for a boolean field,
/// int for an integer one, float otherwise.
py::dict message_dict(const std::vector<reflect::Column>& columns, const void* msg);

/// {field: number} as (field, value) pairs for `topic`; a key that is not a str or a value that is
/// not a real number (bool, int, float, numpy scalar) throws ConfigError naming the topic and
/// the field. The fields' names and ranges are checked where they are held (held_messages.hpp).
std::vector<std::pair<std::string, double>> message_fields(const std::string& topic, const py::dict& fields);

/// A Python value as a parameter value: bool, int, float, str, or a sequence of numbers (a list,
/// tuple or numpy array); anything else throws ConfigError naming `name`.
ParamValue param_value(const std::string& name, const py::handle& value);

/// A parameter value as a Python object.
py::object param_object(const ParamValue& value);

}  // namespace tern::core::python
