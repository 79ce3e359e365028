// core/apps/python/module.cpp: the native module tern._tern (pybind11): tern.fly's flight (the
// CLI's, commands/fly_mission.hpp), tern.Host (python_host.hpp), an MCAP log's tables as CSV
// (export/mcap_csv_export.hpp, for tern.Run), a CSV topic table as a numpy array (python_tables.hpp),
// and tern.Error: ConfigError, ParamError and
// McapError raised as one Python exception whose message names the file, topic, field or
// parameter. The package around it is tern/*.py (docs/python.md).
#include <cstdlib>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/format.h>

#include "commands/command_line.hpp"
#include "commands/fly_mission.hpp"
#include "config/error.hpp"
#include "export/mcap_csv_export.hpp"
#include "mcap/mcap_reader.hpp"
#include "python/python_control.hpp"
#include "python/python_host.hpp"
#include "python/python_tables.hpp"

namespace py = pybind11;
using tern::core::python::PythonControl;
using tern::core::python::PythonFlightOptions;
using tern::core::python::PythonHost;

namespace {

PythonFlightOptions flight_options(std::optional<std::uint64_t> seed, std::optional<double> duration, const py::dict& sets,
                                   std::optional<std::string> log_dir, std::optional<std::string> log_level,
                                   std::optional<std::string> log_format, bool quiet) {
  PythonFlightOptions o;
  for (const auto& [k, v] : sets) {
    const std::string value = py::isinstance<py::bool_>(v) ? (v.cast<bool>() ? "true" : "false") : py::str(v).cast<std::string>();
    o.sets.push_back(fmt::format("{}={}", py::str(k).cast<std::string>(), value));
  }
  o.seed = seed;
  o.duration = duration;
  o.log_dir = std::move(log_dir);
  o.log_level = std::move(log_level);
  o.log_format = std::move(log_format);
  o.quiet = quiet;
  return o;
}

std::string config_or_default(const std::optional<std::string>& config) { return config ? *config : tern::core::default_config().string(); }

py::dict fly(std::optional<std::string> config, std::optional<std::uint64_t> seed, std::optional<double> duration, const py::dict& sets,
             std::optional<std::string> log_dir, std::optional<std::string> log_level, std::optional<std::string> log_format, bool quiet) {
  const PythonFlightOptions o =
      flight_options(seed, duration, sets, std::move(log_dir), std::move(log_level), std::move(log_format), quiet);
  const std::string file = config_or_default(config);
  std::optional<tern::core::FlightResult> r;
  {
    py::gil_scoped_release unlocked;
    r = tern::core::fly_mission(file, tern::core::python::preparation(o), tern::core::python::host_options(o), false);
  }
  if (!r) throw tern::core::ConfigError(fmt::format("tern.fly: {}: the mission check refused it (its errors are printed above)", file));
  py::dict d;
  d["run_dir"] = r->run_dir.string();
  d["ok"] = r->ok;
  d["end_reason"] = r->end_reason;
  d["end_detail"] = r->end_detail;
  d["wall_s"] = r->wall_s;
  return d;
}

// The plugins built with this module: the host looks beside its program (graph/loader.hpp), and
// the program here is python3; so they join TERN_PLUGIN_PATH, after the directories it names.
void add_build_plugins_to_search_path() {
  const char* now = std::getenv("TERN_PLUGIN_PATH");
  const std::string path = now && *now ? std::string(now) + ":" + TERN_PYTHON_PLUGIN_DIR : std::string(TERN_PYTHON_PLUGIN_DIR);
  setenv("TERN_PLUGIN_PATH", path.c_str(), 1);
}

}  // namespace

PYBIND11_MODULE(_tern, m) {
  add_build_plugins_to_search_path();
  m.doc() = "tern's host from Python (docs/python.md); use the package tern, not this module";
  static py::exception<tern::core::ConfigError> error(m, "Error", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const tern::core::ConfigError& e) {
      error(e.what());
    } catch (const tern::ParamError& e) {
      error(e.what());
    } catch (const tern::core::McapError& e) {
      error(e.what());
    }
  });
  m.def(
      "default_config", [] { return tern::core::default_config().string(); }, "the default mission's config file");
  m.def("fly", &fly, py::arg("config") = py::none(), py::kw_only(), py::arg("seed") = py::none(), py::arg("duration") = py::none(),
        py::arg("set") = py::dict(), py::arg("log_dir") = py::none(), py::arg("log_level") = py::none(), py::arg("log_format") = py::none(),
        py::arg("quiet") = true, "one flight as `tern fly` flies it; returns {run_dir, ok, end_reason, end_detail, wall_s}");
  m.def(
      "export_csv", [](const std::string& mcap, const std::string& out_dir) { return tern::core::export_csv(mcap, out_dir).rows; },
      py::arg("mcap"), py::arg("out_dir"), "an MCAP log's topic tables into out_dir/<topic>.csv (tern export csv)");
  m.def("read_table", &tern::core::python::read_table, py::arg("path"), py::arg("dtype"),
        "a topic CSV's rows as an array of the structured dtype made from its header (tern.run.read_table)");
  m.def(
      "bin_dir", [] { return std::string(TERN_PYTHON_BIN_DIR); }, "the build tree's programs (tern, tern-campaign)");
  py::class_<PythonHost>(m, "Host")
      .def(py::init([](std::optional<std::string> config, std::optional<std::uint64_t> seed, std::optional<double> duration,
                       const py::dict& sets, std::optional<std::string> log_dir, std::optional<std::string> log_level,
                       std::optional<std::string> log_format, bool quiet) {
             return std::make_unique<PythonHost>(
                 config_or_default(config),
                 flight_options(seed, duration, sets, std::move(log_dir), std::move(log_level), std::move(log_format), quiet));
           }),
           py::arg("config") = py::none(), py::kw_only(), py::arg("seed") = py::none(), py::arg("duration") = py::none(),
           py::arg("set") = py::dict(), py::arg("log_dir") = py::none(), py::arg("log_level") = py::none(),
           py::arg("log_format") = py::none(), py::arg("quiet") = true)
      .def("reset", &PythonHost::reset, py::arg("seed") = py::none())
      .def("step", &PythonHost::step, py::arg("ticks") = 1)
      .def("step_until", &PythonHost::step_until, py::arg("t"))
      .def_property_readonly("time", &PythonHost::time)
      .def_property_readonly("flying", &PythonHost::flying)
      .def_property_readonly("end_reason", &PythonHost::end_reason)
      .def_property_readonly("seed", &PythonHost::seed)
      .def_property_readonly("base_period", &PythonHost::base_period)
      .def_property_readonly("topics", &PythonHost::topics)
      .def_property_readonly("handovers", &PythonHost::handovers)
      .def_property_readonly("handover_count", &PythonHost::handover_count)
      .def("read", &PythonHost::read, py::arg("topic"), py::arg("fields") = py::none())
      .def("write", &PythonHost::write, py::arg("topic"), py::arg("fields"))
      .def("add_waypoint", &PythonHost::add_waypoint, py::arg("w"), py::arg("Va_d"), py::kw_only(), py::arg("chi_d") = 0.0,
           py::arg("use_chi") = false, py::arg("lla") = false, py::arg("set_current") = false,
           "queues a waypoint (NED m, or lat/lon deg and altitude m with lla=True) for the path planner at the next tick; "
           "set_current: a new list starting with it (ROSplane's add_waypoint); returns the edit's number")
      .def("clear_waypoints", &PythonHost::clear_waypoints, "queues the removal of every waypoint (ROSplane's clear_waypoints)")
      .def("load_mission", &PythonHost::load_mission, py::arg("file"),
           "queues the replacement of the mission by a waypoint file, tern's or ROSplane's (load_mission_from_file)")
      .def("release", &PythonHost::release, py::arg("topic"))
      .def("get_param", &PythonHost::get_param, py::arg("name"))
      .def("set_param", &PythonHost::set_param, py::arg("name"), py::arg("value"))
      .def("swap", &PythonHost::swap, py::arg("instance"), py::arg("so"))
      .def("end", &PythonHost::end)
      .def(
          "control",
          [](PythonHost& h, std::string topic, std::vector<std::string> fields,
             std::vector<std::pair<std::string, std::string>> observation) {
            return std::make_unique<PythonControl>(h, std::move(topic), std::move(fields), std::move(observation));
          },
          py::arg("topic"), py::arg("fields"), py::arg("observation"), py::keep_alive<0, 1>(),
          "a tern.Control: write(topic, fields' values), step(ticks) and read each (topic, field) of observation in one call");
  py::class_<PythonControl>(m, "Control")
      .def("__call__", &PythonControl::operator(), py::arg("action"), py::arg("ticks"),
           "holds action (None: releases the topic), flies ticks, returns (going, observation array)")
      .def("read", &PythonControl::read, "the observation now (0 for a topic not yet published)")
      .def("__len__", &PythonControl::observation_size);
}
