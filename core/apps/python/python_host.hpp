// core/apps/python/python_host.hpp: tern.Host: a mission's Host (flight/host.hpp, the one `tern fly`
// and `tern serve` fly) driven tick by tick from Python:
//   reset(seed)      ends the running flight (its log complete) and starts the next one: every
//                    plugin reset, as `tern serve`'s flights; a new seed builds the host anew
//                    (plugins take their seed when configured) with the swaps made so far
//   step(n)          n ticks of the base rate (Host::tick, the CLI's loop); step_until(t) up to
//                    flight time t s; both return False once the flight has ended
//   read(topic)      the latest message on an output as a dict (tern/python/conversion.hpp); with
//                    fields=[...] those fields' values as a tuple of floats (no dict: quicker)
//   write(topic, d)  fields held on a plugin's output (Host::hold_message) until release(topic);
//                    `pilot`: the pilot's sticks (Host::set_pilot)
//   get_param/set_param, swap(instance, so) between flights (Host::swap), end() -> run dir
//   control(topic, fields, observation) -> tern.Control: write, step and read in one call
//                    (python_control.hpp)
//   add_waypoint(w, Va_d, ...), clear_waypoints(), load_mission(file): mission edits, ROSplane's
//                    services (Host::edit_mission, applied by the path planner at the next tick;
//                    python_mission.cpp)
// Errors are ConfigError / ParamError, raised in Python as tern.Error naming the topic, field or
// parameter.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/pybind11.h>

#include "commands/host_preparation.hpp"
#include "flight/host.hpp"
#include "tern/python/conversion.hpp"

namespace tern::core::python {

namespace py = pybind11;

/// What a tern.Host or tern.fly is asked for, besides the config file.
struct PythonFlightOptions {
  std::vector<std::string> sets;      ///< "instance.param=value", as --set
  std::optional<std::uint64_t> seed;  ///< else the config's
  std::optional<double> duration;     ///< s, else the config's
  std::optional<std::string> log_dir;
  std::optional<std::string> log_level;   ///< summary, decimated or full (--log-level)
  std::optional<std::string> log_format;  ///< csv, mcap or both (--log-format)
  bool quiet = true;                      ///< console log: warnings only
};

/// The CLI's preparation and host options for `o` (fly_mission.hpp, Host).
HostPreparation preparation(const PythonFlightOptions& o);
HostOptions host_options(const PythonFlightOptions& o);

class PythonHost {
 public:
  /// Builds the host (plugins loaded and configured, ports bound); no flight yet. Throws
  /// ConfigError: the config's errors, or the mission check's errors in one message.
  PythonHost(std::string config_file, PythonFlightOptions options);
  ~PythonHost();

  void reset(std::optional<std::uint64_t> seed);
  bool step(std::int64_t ticks);
  bool step_until(double t_s);
  double time() const;
  bool flying() const { return running_; }
  /// Why the flight ended ("" while it goes on or before the first).
  const std::string& end_reason() const { return end_reason_; }
  std::uint64_t seed() const { return seed_; }
  double base_period() const;
  std::vector<std::string> topics() const;
  /// The running (or last) flight's controller handovers (the safety net's: phase_router.hpp)
  /// as dicts {t [s], from, to, reason}.
  py::list handovers() const;
  /// How many handovers the running (or last) flight has had: len(handovers) without building them.
  std::size_t handover_count() const { return host_->handovers().size(); }
  py::object read(const std::string& topic, const std::optional<std::vector<std::string>>& fields) const;
  void write(const std::string& topic, const py::dict& fields);
  /// write() of (field, value) pairs.
  void write_fields(const std::string& topic, const std::vector<std::pair<std::string, double>>& fields);
  /// The output publishing `topic` now (its current producer); ConfigError naming the mission's
  /// topics when there is none.
  const OutputBase& topic_output(const std::string& topic) const;
  /// `field`'s column in `output`'s message type; ConfigError listing its fields when it has none.
  const reflect::Column& field_column(const std::string& topic, const OutputBase& output, const std::string& field) const;
  bool release(const std::string& topic) { return host_->release_message(topic); }
  py::object get_param(const std::string& name) const;
  void set_param(const std::string& name, const py::handle& value);
  void swap(const std::string& instance, const std::string& so);
  /// Mission edits (python_mission.cpp), each queued for the next tick; the edit's number.
  /// Throws ConfigError for a non-finite waypoint, Va_d <= 0, a missing file, or a mission
  /// whose planner takes no edits.
  std::uint32_t add_waypoint(const std::array<double, 3>& w, double Va_d, double chi_d, bool use_chi, bool lla, bool set_current);
  std::uint32_t clear_waypoints();
  std::uint32_t load_mission(const std::string& file);
  /// Ends the running flight (end_reason "aborted" when it was still going; a flight whose tick
  /// ended it is ended at once); the run directory of the last flight ("" before the first).
  std::string end();

 private:
  void build();
  void begin();
  std::string topic_list() const;
  /// The log columns of a message type, computed once per type.
  const tern::python::MessageColumns& columns_of(const MsgType& type) const;

  std::string config_file_;
  PythonFlightOptions options_;
  std::uint64_t seed_ = 1;
  std::unique_ptr<Host> host_;
  std::vector<std::pair<std::string, std::string>> swaps_;  // (instance, library), re-applied on a rebuild
  std::uint32_t edits_ = 0;                                 // mission edits sent (their numbers)
  bool running_ = false;                                    // between begin_flight() and end_flight()
  std::string end_reason_;
  std::string last_run_dir_;
  Nanos ended_at_ = 0;
  mutable std::map<std::string, tern::python::MessageColumns, std::less<>> columns_;  // by message type name
};

}  // namespace tern::core::python
