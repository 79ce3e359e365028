// plugins/python/src/message_objects.hpp: tern's messages as a Python plugin's objects and back, by
// their log columns (tern/reflect.hpp layout<T>(): "phi", "p_n", "r_n", "quat_w", "aux_0" ...), so a
// Python plugin sees the names the flight log and `tern.Run` use. The columns' values are the
// SDK's Python conversion (tern/python/conversion.hpp), the one tern.Host's dicts are made with.
//
// In:  a message is a types.SimpleNamespace with one attribute per column: bool for a boolean
//      column, int for an integer one (stamp: ns), float otherwise (SI units, the log's).
// Out: a mapping {column: value} (a dict, or any object's vars(), e.g. a SimpleNamespace) fills
//      a default message of the output's type: the columns it names, the rest as the message's
//      defaults; `stamp` the step's time unless given. A column the type does not have, a value
//      of the wrong kind (text for a number, 0.5 for an integer) or out of an integer column's
//      range throws PythonError naming the output, the column and the value.
#pragma once

#include <Python.h>

#include <string>
#include <unordered_map>
#include <vector>

#include "interpreter.hpp"
#include "tern/python/conversion.hpp"
#include "tern/reflect.hpp"
#include "tern/time.hpp"

namespace tern::python_plugin {

/// One message type's columns as a plugin's objects. Destroy it with the GIL held.
class MessageObjects {
 public:
  MessageObjects(std::string type_name, std::vector<reflect::Column> columns);
  /// The message at `bytes` as a new SimpleNamespace.
  Ref to_python(const void* bytes) const;
  /// Fills the message at `bytes` (already a default message) from `fields` (see above) for the
  /// output `port`; `now` is the stamp unless `fields` sets one.
  void from_python(PyObject* fields, void* bytes, Nanos now, const std::string& port) const;

 private:
  void set(const reflect::Column& c, PyObject* value, void* bytes, const std::string& port) const;
  std::string names() const;

  std::string type_name_;
  python::MessageColumns columns_;
  std::unordered_map<std::string, std::size_t> index_;
  const reflect::Column* stamp_ = nullptr;
};

}  // namespace tern::python_plugin
