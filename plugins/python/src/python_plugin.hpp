// plugins/python/src/python_plugin.hpp: a plugin written in Python (docs/python.md, "A plugin in
// Python"). The mission config names the script and its class:
//
//   - name: follower
//     plugin: python_path_follower        # python_controller, python_estimator, python_path_manager,
//     rate: 100                           # python_path_follower, python_generic: the kind the host sees
//     params: {script: follower.py, class: PathFollower, k_path: 0.02}
//
// The class declares its ports and parameters as class attributes, and lives a flight:
//
//   class PathFollower:
//       inputs = {"state": "State", "current_path": "CurrentPath"}   # port: tern message type
//       outputs = {"controller_command": "ControllerCommand"}
//       params = {"k_path": (0.0175, "1/m", 1e-5, 10.0, "line gain")}  # default[, unit, min, max, description]
//       def __init__(self): ...              # per-flight state; the parameters are attributes already
//       def step(self, now, inputs):         # now: ns; inputs: {port: message or None}
//           return {"controller_command": {"Va_c": ..., "chi_c": ...}}   # or None: nothing published
//       # optional: start(self), stop(self), summary(self) -> {name: float},
//       #           take_over(self, last_command) (a controller handed the controls; default: a new instance)
//
// An input may be declared {"type": "Rc", "need": "optional", "description": "..."}; a message
// type is the name after "tern/" (State, Imu, ControllerCommand ...: tern/msg/all.hpp). Messages
// are SimpleNamespace objects with the log's columns (message_objects.hpp). A parameter's Python
// type sets its kind: bool, int, float, str, or a list of numbers; each is an attribute of the
// instance, updated before the next call when it changes in flight. Also set before __init__:
// `seed` (the instance's seed, for numpy's generators), `instance` (its name), `log` (a
// logging.Logger whose records go to the instance's log: console and tern.log).
//
// Per flight a new instance (the host's reset() and the default take_over()): nothing a flight
// changes outlives it, the contract of tern/plugin.hpp. The script is imported once per instance
// as its own module (two instances of one script share no globals), its directory on sys.path.
//
// Errors: a Python exception in any call is a throw of this plugin, one line naming the script's
// file, line, function and exception; the host then does what it does for any plugin that throws
// (a routed controller: the fallback flies; anything else: the flight ends, its log kept). A hang
// is the watchdog's (in-process) or the isolation's (`isolate: true`, child killed). A script,
// class or declaration that is wrong fails configure() with one line naming it.
#pragma once

#include <Python.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "interpreter.hpp"
#include "message_objects.hpp"
#include "tern/plugin.hpp"

namespace tern::python_plugin {

class PythonPlugin final : public Plugin {
 public:
  PythonPlugin() = default;
  ~PythonPlugin() override;

  void configure() override;
  void start() override;
  void step(Nanos now) override;
  void reset() override;
  void take_over(const msg::Actuators& last_command) override;
  void stop() override;
  std::vector<std::pair<std::string, double>> summary() const override;

 private:
  struct InputSlot {
    InputBase* port;
    std::shared_ptr<const MessageObjects> columns;
    Ref key;                      ///< the port's name as a Python string
    std::uint64_t converted = 0;  ///< the source's sequence number `message` was made from
    Ref message;                  ///< the latest message as a Python object (None before one)
  };
  struct OutputSlot {
    OutputBase* port;
    std::shared_ptr<const MessageObjects> columns;
    std::function<void*()> fresh;   ///< a default message of the port's type, to fill
    std::function<void()> publish;  ///< publishes what fresh() returned
  };
  struct PythonParam {
    ParamBase* param;
    Ref name;
  };

  void load_class();
  void declare_ports(const char* attribute, bool input);
  void declare_port(const std::string& port, PyObject* spec, bool input);
  template <class T>
  void add_input(const std::string& port, const std::string& description, Need need);
  template <class T>
  void add_output(const std::string& port, const std::string& description);
  void declare_params();
  template <class T>
  void add_param(const std::string& name, T default_value, ParamSpec spec);
  void new_instance();
  void push_params();
  Ref call(const char* method, PyObject* args = nullptr);
  Ref inputs_dict();
  void publish(PyObject* outputs, Nanos now);
  void drain_log();
  std::vector<std::pair<std::string, double>> summary_figures() const;
  [[noreturn]] void fail(const std::string& what) const;

  Param<std::string> script_, class_name_;
  std::string module_name_;
  Ref module_, cls_, instance_, log_queue_, logger_;
  std::vector<InputSlot> inputs_py_;
  std::vector<OutputSlot> outputs_py_;
  std::vector<PythonParam> params_py_;
  std::vector<std::unique_ptr<PortBase>> owned_ports_;
  std::vector<std::unique_ptr<ParamBase>> owned_params_;
  std::atomic<bool> params_changed_{false};  ///< a parameter changed (possibly on another thread)
};

}  // namespace tern::python_plugin
