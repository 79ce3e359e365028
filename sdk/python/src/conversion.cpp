// Messages and parameters to Python and back. See tern/python/conversion.hpp.
#include "tern/python/conversion.hpp"

#include <cstdint>
#include <cstring>
#include <variant>

#include <fmt/format.h>
#include <pybind11/stl.h>

namespace tern::python {

namespace {

template <class T>
T read_as(const void* msg, std::size_t offset) {
  T v;
  std::memcpy(&v, static_cast<const char*>(msg) + offset, sizeof(T));
  return v;
}

std::int64_t exact_integer(py::handle value, std::string_view subject) {
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
  if (overflow != 0) throw ConversionError(fmt::format("{} {}: beyond a 64-bit integer", subject, repr_of(value)));
  if (v == -1 && PyErr_Occurred() != nullptr) throw py::error_already_set();
  return v;
}

std::vector<double> numbers(py::handle value, std::string_view subject) {
  const py::object items = py::hasattr(value, "tolist") ? value.attr("tolist")() : py::reinterpret_borrow<py::object>(value);
  std::vector<double> out;
  for (const py::handle item : items) {
    const std::optional<double> x = number(item);
    if (!x) throw ConversionError(fmt::format("{} {}: element {} is not a number", subject, repr_of(value), out.size()));
    out.push_back(*x);
  }
  return out;
}

}  // namespace

py::object column_object(const reflect::Column& c, const void* msg) {
  using reflect::Scalar;
  switch (c.kind) {
    case Scalar::f64: return py::float_(read_as<double>(msg, c.offset));
    case Scalar::f32: return py::float_(read_as<float>(msg, c.offset));
    case Scalar::i64: return py::int_(read_as<std::int64_t>(msg, c.offset));
    case Scalar::i32: return py::int_(read_as<std::int32_t>(msg, c.offset));
    case Scalar::i16: return py::int_(read_as<std::int16_t>(msg, c.offset));
    case Scalar::i8: return py::int_(read_as<std::int8_t>(msg, c.offset));
    case Scalar::u64: return py::int_(read_as<std::uint64_t>(msg, c.offset));
    case Scalar::u32: return py::int_(read_as<std::uint32_t>(msg, c.offset));
    case Scalar::u16: return py::int_(read_as<std::uint16_t>(msg, c.offset));
    case Scalar::u8: return py::int_(read_as<std::uint8_t>(msg, c.offset));
    case Scalar::boolean: break;
  }
  return py::bool_(read_as<bool>(msg, c.offset));
}

MessageColumns::MessageColumns(std::vector<reflect::Column> columns) : columns_(std::move(columns)) {
  keys_.reserve(columns_.size());
  for (const auto& c : columns_) {
    PyObject* key = PyUnicode_InternFromString(c.name.c_str());
    if (key == nullptr) throw py::error_already_set();
    keys_.push_back(py::reinterpret_steal<py::str>(key));
  }
}

py::dict MessageColumns::to_dict(const void* msg) const {
  py::dict d;
  for (std::size_t i = 0; i < columns_.size(); ++i) d[keys_[i]] = column_object(columns_[i], msg);
  return d;
}

std::optional<double> number(py::handle value) {
  if (PyBool_Check(value.ptr())) return value.ptr() == Py_True ? 1.0 : 0.0;
  if (PyUnicode_Check(value.ptr()) || PyBytes_Check(value.ptr()) || PyComplex_Check(value.ptr()) || PyNumber_Check(value.ptr()) == 0)
    return std::nullopt;
  PyObject* f = PyNumber_Float(value.ptr());
  if (f == nullptr) {
    PyErr_Clear();
    return std::nullopt;
  }
  const double x = PyFloat_AS_DOUBLE(f);
  Py_DECREF(f);
  return x;
}

std::string repr_of(py::handle value) { return py::repr(value).cast<std::string>(); }

py::object param_object(const ParamValue& value) {
  return std::visit([](const auto& v) -> py::object { return py::cast(v); }, value);
}

ParamValue param_value(py::handle value, std::string_view subject) {
  if (PyBool_Check(value.ptr())) return value.ptr() == Py_True;
  if (PyLong_Check(value.ptr())) return exact_integer(value, subject);
  if (PyFloat_Check(value.ptr())) return PyFloat_AS_DOUBLE(value.ptr());
  if (PyUnicode_Check(value.ptr())) return value.cast<std::string>();
  if (const std::optional<double> x = number(value)) return *x;  // a numpy scalar
  if (PySequence_Check(value.ptr()) != 0 || py::hasattr(value, "tolist")) return numbers(value, subject);
  throw ConversionError(fmt::format("{} of bool, int, float, str or a list of numbers, not {}", subject, repr_of(value)));
}

}  // namespace tern::python
