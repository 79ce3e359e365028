// core/apps/python/python_control.hpp: tern.Control, a learning environment's step in one call
// (tern.env.FlightEnv.step): an action held on a topic's fields, ticks flown, an observation read.
// It is exactly write(topic, dict(zip(fields, action))) (None: release(topic)), step(ticks) and
// read(topic, [field]) for each observation pair, in that order, on the Host it was made from
// (python_host.hpp), with the names resolved once per message type instead of in Python at every
// step: the flight is the same, bit for bit.
//   control = host.control("actuators", ["delta_a"], [("state", "phi"), ("state", "p")])
//   going, obs = control(np.array([0.1]), 4)     # obs: a float64 array, the pairs' order
//   obs = control.read()                         # the observation without stepping
// A topic nobody has published yet reads 0 (Host.read's fields). Errors as Host.read and
// Host.write raise them (tern.Error naming the topic or field); a wrong action size names both.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "graph/message_columns.hpp"

namespace tern::core::python {

namespace py = pybind11;

class PythonHost;

class PythonControl {
 public:
  /// `host` must outlive the control (the binding keeps it alive). Throws ConfigError for an
  /// empty `fields`.
  PythonControl(PythonHost& host, std::string topic, std::vector<std::string> fields,
                std::vector<std::pair<std::string, std::string>> observation);

  /// Holds `action` (as many values as fields; None: releases the topic), flies `ticks` ticks,
  /// reads the observation: (going, obs), going as Host.step's return.
  py::tuple operator()(const std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>& action, std::int64_t ticks);
  /// The observation now, a float64 array in the pairs' order.
  py::array_t<double> read();
  std::size_t observation_size() const { return observation_.size(); }

 private:
  struct Pair {
    std::string topic, field;
    std::string type;                         // the message type the column was found in
    const reflect::Column* column = nullptr;  // in PythonHost's columns_of(type): stable
  };
  void read_into(double* out);

  PythonHost& host_;
  std::string topic_;
  std::vector<std::pair<std::string, double>> action_;  // the fields, their values set per step
  std::vector<Pair> observation_;
};

}  // namespace tern::core::python
