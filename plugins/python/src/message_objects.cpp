// Messages to Python and back by their log columns. See message_objects.hpp.
#include "message_objects.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>

#include <fmt/format.h>

namespace tern::python_plugin {

namespace {

template <class T>
void write_as(void* bytes, std::size_t offset, T v) {
  std::memcpy(static_cast<char*>(bytes) + offset, &v, sizeof(T));
}

// The integer range of an integer column.
std::pair<long double, long double> integer_range(reflect::Scalar k) {
  using reflect::Scalar;
  const auto range = [](auto zero) {
    using T = decltype(zero);
    return std::pair<long double, long double>{std::numeric_limits<T>::min(), std::numeric_limits<T>::max()};
  };
  switch (k) {
    case Scalar::i64: return range(std::int64_t{});
    case Scalar::i32: return range(std::int32_t{});
    case Scalar::i16: return range(std::int16_t{});
    case Scalar::i8: return range(std::int8_t{});
    case Scalar::u64: return range(std::uint64_t{});
    case Scalar::u32: return range(std::uint32_t{});
    case Scalar::u16: return range(std::uint16_t{});
    default: return range(std::uint8_t{});
  }
}

template <class T>
void write_integer(void* m, std::size_t offset, long long v) {
  write_as<T>(m, offset, static_cast<T>(v));
}

void write_integer_column(const reflect::Column& c, void* m, long long v) {
  using reflect::Scalar;
  switch (c.kind) {
    case Scalar::i64: write_integer<std::int64_t>(m, c.offset, v); break;
    case Scalar::i32: write_integer<std::int32_t>(m, c.offset, v); break;
    case Scalar::i16: write_integer<std::int16_t>(m, c.offset, v); break;
    case Scalar::i8: write_integer<std::int8_t>(m, c.offset, v); break;
    case Scalar::u64: write_integer<std::uint64_t>(m, c.offset, v); break;
    case Scalar::u32: write_integer<std::uint32_t>(m, c.offset, v); break;
    case Scalar::u16: write_integer<std::uint16_t>(m, c.offset, v); break;
    default: write_integer<std::uint8_t>(m, c.offset, v); break;
  }
}

bool is_integer_kind(reflect::Scalar k) { return k != reflect::Scalar::f64 && k != reflect::Scalar::f32 && k != reflect::Scalar::boolean; }

}  // namespace

MessageObjects::MessageObjects(std::string type_name, std::vector<reflect::Column> columns)
    : type_name_(std::move(type_name)), columns_(std::move(columns)) {
  const auto& cs = columns_.columns();
  for (std::size_t i = 0; i < cs.size(); ++i) {
    index_.emplace(cs[i].name, i);
    if (cs[i].name == "stamp" && cs[i].kind == reflect::Scalar::i64) stamp_ = &cs[i];
  }
}

Ref MessageObjects::to_python(const void* bytes) const {
  const python::py::dict kwargs = columns_.to_dict(bytes);
  static PyObject* namespace_type = nullptr;  // types.SimpleNamespace, alive as long as the interpreter
  if (namespace_type == nullptr) {
    Ref types = Ref::take(PyImport_ImportModule("types"));
    namespace_type = Ref::take(PyObject_GetAttrString(types.get(), "SimpleNamespace")).get();
    Py_INCREF(namespace_type);
  }
  Ref no_args = Ref::take(PyTuple_New(0));
  return Ref::take(PyObject_Call(namespace_type, no_args.get(), kwargs.ptr()));
}

void MessageObjects::from_python(PyObject* fields, void* bytes, Nanos now, const std::string& port) const {
  if (stamp_ != nullptr) write_as<std::int64_t>(bytes, stamp_->offset, now);
  Ref mapping = PyDict_Check(fields) ? Ref::borrow(fields) : Ref::take(PyObject_GetAttrString(fields, "__dict__"));
  if (!PyDict_Check(mapping.get()))
    throw PythonError(fmt::format("output '{}': a {} message is a dict {{column: value}} or an object with attributes, not {}", port,
                                  type_name_, text_of(reinterpret_cast<PyObject*>(Py_TYPE(fields)))));
  PyObject *key = nullptr, *value = nullptr;
  Py_ssize_t pos = 0;
  while (PyDict_Next(mapping.get(), &pos, &key, &value)) {
    const std::string name = text_of(key);
    const auto it = index_.find(name);
    if (it == index_.end())
      throw PythonError(fmt::format("output '{}': {} has no column '{}' (its columns: {})", port, type_name_, name, names()));
    set(columns_.columns()[it->second], value, bytes, port);
  }
}

void MessageObjects::set(const reflect::Column& c, PyObject* value, void* bytes, const std::string& port) const {
  const auto wrong = [&](const char* wanted) {
    return PythonError(fmt::format("output '{}': column '{}' of {} takes {}, not {}", port, c.name, type_name_, wanted, text_of(value)));
  };
  const std::optional<double> number = python::number(value);
  if (c.kind == reflect::Scalar::boolean) {  // True/False, or a number that is 0 or 1 (numpy's bool_, 1.0)
    if (!number || (*number != 0.0 && *number != 1.0)) throw wrong("a bool");
    write_as<bool>(bytes, c.offset, *number == 1.0);
    return;
  }
  if (!number) throw wrong(is_integer_kind(c.kind) ? "an integer" : "a number");
  const double x = *number;
  if (!is_integer_kind(c.kind)) {
    if (c.kind == reflect::Scalar::f32)
      write_as<float>(bytes, c.offset, static_cast<float>(x));
    else
      write_as<double>(bytes, c.offset, x);
    return;
  }
  const auto [lo, hi] = integer_range(c.kind);
  if (!std::isfinite(x) || x != std::floor(x) || static_cast<long double>(x) < lo || static_cast<long double>(x) > hi)
    throw wrong("an integer in its range");
  if (PyLong_Check(value)) {  // exact for 64-bit stamps, which a double would round
    const long long v = PyLong_AsLongLong(value);
    if (v == -1 && PyErr_Occurred() != nullptr) throw_python_error();
    write_integer_column(c, bytes, v);
  } else {
    write_integer_column(c, bytes, static_cast<long long>(x));
  }
}

std::string MessageObjects::names() const {
  std::string out;
  for (const auto& c : columns_.columns()) out += (out.empty() ? "" : ", ") + c.name;
  return out;
}

}  // namespace tern::python_plugin
