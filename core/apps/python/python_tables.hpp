// core/apps/python/python_tables.hpp: a topic table of the CSV log (topics/<name>.csv, written by
// core/formats/csv/csv_rows.hpp) parsed into a numpy structured array for tern.Run (tern/run.py). tern.Run
// makes the array's dtype from the header (a column's kind and unit); this fills it: every cell
// with std::from_chars (the exact inverse of the log's std::to_chars), the rows split over two
// threads, without the GIL. Errors throw ConfigError naming the file, line and column.
#pragma once

#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace tern::core::python {

namespace py = pybind11;

/// The rows of `path` (its header line skipped) as an array of `dtype`, a structured dtype of one
/// field per column in the header's order, each float64, int64 or bool.
py::array read_table(const std::string& path, const py::dtype& dtype);

}  // namespace tern::core::python
