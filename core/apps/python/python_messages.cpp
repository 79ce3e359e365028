#include "python/python_messages.hpp"

#include <optional>
#include <variant>

#include <fmt/format.h>
#include <pybind11/stl.h>

#include "config/error.hpp"
#include "graph/message_columns.hpp"

namespace tern::core::python {

namespace {

bool is_integer_kind(reflect::Scalar k) { return k != reflect::Scalar::f64 && k != reflect::Scalar::f32 && k != reflect::Scalar::boolean; }

std::string text_of(const py::handle& v) { return py::repr(v).cast<std::string>(); }

/// A real number from Python (bool, int, float, numpy scalar), or nullopt.
std::optional<double> number(const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? 1.0 : 0.0;
  if (py::isinstance<py::str>(v) || py::isinstance<py::bytes>(v) || !PyNumber_Check(v.ptr()) || PyComplex_Check(v.ptr()))
    return std::nullopt;
  PyObject* f = PyNumber_Float(v.ptr());
  if (f == nullptr) {
    PyErr_Clear();
    return std::nullopt;
  }
  const double x = PyFloat_AsDouble(f);
  Py_DECREF(f);
  return x;
}

}  // namespace

py::dict message_dict(const std::vector<reflect::Column>& columns, const void* msg) {
  py::dict d;
  for (const auto& c : columns) {
    const double v = column_value(c, msg);
    if (c.kind == reflect::Scalar::boolean)
      d[py::str(c.name)] = py::bool_(v != 0.0);
    else if (is_integer_kind(c.kind))
      d[py::str(c.name)] = py::int_(static_cast<long long>(v));
    else
      d[py::str(c.name)] = py::float_(v);
  }
  return d;
}

std::vector<std::pair<std::string, double>> message_fields(const std::string& topic, const py::dict& fields) {
  std::vector<std::pair<std::string, double>> out;
  for (const auto& [key, value] : fields) {
    if (!py::isinstance<py::str>(key)) throw ConfigError(fmt::format("topic '{}': field name {} is not a str", topic, text_of(key)));
    const std::string name = key.cast<std::string>();
    const std::optional<double> x = number(value);
    if (!x) throw ConfigError(fmt::format("topic '{}': field '{}': {} is not a number", topic, name, text_of(value)));
    out.emplace_back(name, *x);
  }
  return out;
}

ParamValue param_value(const std::string& name, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) return value.cast<std::int64_t>();
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (const std::optional<double> x = number(value)) return *x;  // a numpy scalar
  if (py::isinstance<py::sequence>(value) || py::hasattr(value, "tolist")) {
    const py::object items = py::hasattr(value, "tolist") ? value.attr("tolist")() : py::reinterpret_borrow<py::object>(value);
    std::vector<double> v;
    for (const auto& item : items) {
      const std::optional<double> x = number(item);
      if (!x) throw ConfigError(fmt::format("parameter '{}': element {} of {} is not a number", name, v.size(), text_of(value)));
      v.push_back(*x);
    }
    return v;
  }
  throw ConfigError(fmt::format("parameter '{}': {} is not a bool, int, float, str or list of numbers", name, text_of(value)));
}

py::object param_object(const ParamValue& value) {
  return std::visit([](const auto& v) -> py::object { return py::cast(v); }, value);
}

}  // namespace tern::core::python
