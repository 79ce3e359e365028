// tern-fcu: `tern fcu param list|get|set`, `tern fcu calibrate imu|gyro|baro|airspeed`,
// `tern fcu status` - a ROSflight FCU's firmware parameters, calibrations and state over its
// MAVLink link (serial port or UDP). Not while flying: the flight holds the port.
//
//   tern fcu --device /dev/ttyACM0 status              (version, arming, errors, TIMESYNC round trip)
//   tern fcu --device /dev/ttyACM0 param list
//   tern fcu param get RC_ATT_OVRD_CHN
//   tern fcu param set MOTOR_IDLE_THR 0.15 --write      (--write: save to the FCU's flash)
//   tern fcu calibrate imu                              (level and still; then param write)
//
// Requests go to the system id of the FCU's own frames (comm_manager.cpp ignores any other
// target_system). A set is confirmed by reading the value back: the firmware echoes PARAM_VALUE
// only when a value changes and ignores a PARAM_SET of the other type (comm_manager.cpp
// param_set_*_callback, param.cpp set_param_*). Commands are refused while armed.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "tern_fcu_serial/codec.hpp"
#include "tern_fcu_serial/fcu_side.hpp"
#include "tern_fcu_serial/link.hpp"
#include "tern_fcu_serial/status.hpp"
#include "tern_fcu_serial/timesync.hpp"

namespace {

namespace fcu = tern::fcu;
namespace mav = tern::fcu::mavlink;

struct Client {
  fcu::Link link;
  mav::Encoder enc{1, 50};
  std::deque<fcu::Received> rx;
  std::uint8_t target = 0;  ///< the FCU's system id, from its frames
  explicit Client(const fcu::LinkOptions& o) : link(o) {
    link.start();
    mav::Heartbeat h;  // the firmware holds its STATUSTEXT until a companion's HEARTBEAT
    h.type = 18;
    h.autopilot = 8;
    h.mavlink_version = 3;
    send(h);
  }
  /// Waits for the FCU's first frame (HEARTBEAT at 1 Hz, sensors faster) for its system id.
  bool find_target(double timeout_s) {
    return collect_frames(timeout_s, [&](const fcu::Received& r) {
      if (r.frame.compid != fcu::kFirmwareComponent) return false;
      target = r.frame.sysid;
      return true;
    });
  }
  template <class F>
  bool collect_frames(double timeout_s, F&& done) {
    const std::int64_t deadline = fcu::steady_ns() + static_cast<std::int64_t>(timeout_s * 1e9);
    for (;;) {
      link.drain(rx);
      while (!rx.empty()) {
        const fcu::Received r = rx.front();
        rx.pop_front();
        if (done(r)) return true;
      }
      const std::int64_t left = deadline - fcu::steady_ns();
      if (left <= 0) return false;
      link.wait(left);
    }
  }

  template <class T>
  void send(const T& m) {
    link.send(enc.frame(m));
  }

  /// Collects decoded messages until `done` returns true or `timeout_s` passes without progress.
  template <class F>
  bool collect(double timeout_s, F&& done) {
    std::int64_t deadline = fcu::steady_ns() + static_cast<std::int64_t>(timeout_s * 1e9);
    for (;;) {
      link.drain(rx);
      while (!rx.empty()) {
        const auto m = mav::decode(rx.front().frame);
        rx.pop_front();
        if (m && done(*m, deadline)) return true;
      }
      const std::int64_t left = deadline - fcu::steady_ns();
      if (left <= 0) return false;
      link.wait(left);
    }
  }
};

std::string format_value(const mav::ParamValue& v) {
  const double x = fcu::param_number(v.param_value, v.param_type);
  char buf[64];
  if (v.param_type == fcu::kParamReal32)
    std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(v.param_value));
  else
    std::snprintf(buf, sizeof buf, "%.0f", x);
  return buf;
}
// MAV_PARAM_TYPE of the dialect (rosflight_firmware comms/mavlink/rosflight.xml, enum MAV_PARAM_TYPE),
// the types of ROSflight's PARAM_VALUE.
const char* type_name(std::uint8_t t) {
  switch (t) {
    case 1: return "uint8";
    case 2: return "int8";
    case 3: return "uint16";
    case 4: return "int16";
    case 5: return "uint32";
    case 6: return "int32";
    case 9: return "float";
    default: return "?";
  }
}

std::optional<mav::ParamValue> read_param(Client& c, const std::string& name, double timeout) {
  std::optional<mav::ParamValue> got;
  for (int attempt = 0; attempt < 3 && !got; ++attempt) {
    mav::ParamRequestRead r;
    r.target_system = c.target;
    r.target_component = 1;
    r.param_id = mav::to_chars<16>(name);
    r.param_index = -1;
    c.send(r);
    c.collect(timeout, [&](const mav::Message& m, std::int64_t&) {
      const auto* v = std::get_if<mav::ParamValue>(&m);
      if (v && mav::to_string(v->param_id) == name) got = *v;
      return got.has_value();
    });
  }
  return got;
}

/// Sends ROSFLIGHT_CMD c and waits for its acknowledgement; prints the outcome.
bool command(Client& c, fcu::RosflightCmd which, double timeout) {
  mav::RosflightCmd cmd;
  cmd.command = static_cast<std::uint8_t>(which);
  c.send(cmd);
  std::optional<bool> ok;
  c.collect(timeout * 3, [&](const mav::Message& m, std::int64_t&) {
    const auto* a = std::get_if<mav::RosflightCmdAck>(&m);
    if (a && a->command == cmd.command) ok = a->success != 0;
    return ok.has_value();
  });
  if (!ok)
    std::cerr << "tern fcu: no acknowledgement of command " << int(cmd.command) << "\n";
  else if (!*ok)
    std::cerr << "tern fcu: the FCU refused command " << int(cmd.command) << " (armed?)\n";
  else if (which == fcu::RosflightCmd::write_params)
    std::printf("written to flash\n");
  return ok.value_or(false);
}

/// ROSFLIGHT_CMD *_CALIBRATION, then the firmware's STATUSTEXT verdict (sensors.cpp
/// calibrate_accel: about 2.5 s at 400 Hz; calibrate_baro / calibrate_diff_pressure: 255
/// cycles of > 20 ms, about 8 s).
int run_calibration(Client& c, const std::string& what, double timeout) {
  const std::map<std::string, std::pair<fcu::RosflightCmd, std::string>> kinds = {
      {"imu", {fcu::RosflightCmd::accel_calibration, "IMU offsets captured"}},
      {"gyro", {fcu::RosflightCmd::gyro_calibration, ""}},
      {"baro", {fcu::RosflightCmd::baro_calibration, "Baro ground pressure cal successful!"}},
      {"airspeed", {fcu::RosflightCmd::airspeed_calibration, "Airspeed Cal Successful!"}}};
  const auto& [cmd, success] = kinds.at(what);
  if (!command(c, cmd, timeout)) return 1;
  if (success.empty()) {
    std::printf("gyro calibration started (about 2.5 s, keep still)\n");
    return 0;
  }
  std::optional<std::string> verdict;
  c.collect(std::max(timeout, 15.0), [&](const mav::Message& m, std::int64_t&) {
    const auto* t = std::get_if<mav::Statustext>(&m);
    if (!t) return false;
    const std::string text = mav::to_string(t->text);
    if (text == success || t->severity <= 3) verdict = text;
    return verdict.has_value();
  });
  if (!verdict) {
    std::cerr << "tern fcu: no verdict on the " << what << " calibration from the FCU\n";
    return 1;
  }
  if (*verdict != success) {
    std::cerr << "tern fcu: " << what << " calibration failed: " << *verdict << "\n";
    return 1;
  }
  std::printf("%s: %s (save it with `tern fcu param write`)\n", what.c_str(), verdict->c_str());
  return 0;
}

/// `status`: the firmware's version (ROSFLIGHT_CMD_SEND_VERSION), its state (ROSFLIGHT_STATUS,
/// 10 Hz) and the link's round trip: `samples` TIMESYNC requests at `rate` Hz, each answered by
/// the firmware's main loop (comm_manager.cpp CommManager::timesync_callback, through
/// ROSflight::run -> MavlinkAdapter::receive -> handle_msg_timesync); the round trip is the
/// answer's arrival (stamped by the link's reader thread) minus the request's send time, the
/// same figure as a flight's fcu_timesync_rtt_* (timesync.hpp).
int run_status(Client& c, int samples, double rate, double timeout) {
  mav::RosflightCmd ver;
  ver.command = static_cast<std::uint8_t>(fcu::RosflightCmd::send_version);
  c.send(ver);
  std::optional<std::string> version;
  std::optional<bool> version_refused;  // the firmware answers SEND_VERSION only disarmed (comm_manager.cpp command_callback)
  std::optional<mav::RosflightStatus> status;
  fcu::TimeSync ts;
  const auto period = static_cast<std::int64_t>(1e9 / rate);
  int sent = 0;
  std::int64_t next = fcu::steady_ns();
  const std::int64_t deadline = next + static_cast<std::int64_t>((samples / rate + std::max(timeout, 1.0)) * 1e9);
  for (;;) {
    const std::int64_t now = fcu::steady_ns();
    if (sent < samples && now >= next) {
      c.send(fcu::TimeSync::request(now));
      ++sent;
      next += period;
    }
    c.link.drain(c.rx);
    while (!c.rx.empty()) {
      const fcu::Received r = c.rx.front();
      c.rx.pop_front();
      const auto m = mav::decode(r.frame);
      if (!m) continue;
      if (const auto* t = std::get_if<mav::Timesync>(&*m))
        ts.on_answer(*t, r.rx_ns);
      else if (const auto* v = std::get_if<mav::RosflightVersion>(&*m))
        version = mav::to_string(v->version);
      else if (const auto* st = std::get_if<mav::RosflightStatus>(&*m))
        status = *st;
      else if (const auto* a = std::get_if<mav::RosflightCmdAck>(&*m); a && a->command == ver.command && a->success == 0)
        version_refused = true;
    }
    const bool answered = ts.samples() + ts.rejected() >= static_cast<std::uint64_t>(samples);
    if ((answered && (version || version_refused) && status) || fcu::steady_ns() >= deadline) break;
    const std::int64_t wake = sent < samples ? std::min(next, deadline) : deadline;
    c.link.wait(std::max<std::int64_t>(0, wake - fcu::steady_ns()));
  }
  std::printf("FCU:        system %d on %s, firmware %s\n", int(c.target), c.link.options().describe().c_str(),
              version           ? version->c_str()
              : version_refused ? "(not told: the firmware answers SEND_VERSION only when disarmed)"
                                : "(no ROSFLIGHT_VERSION answer)");
  if (status) {
    const std::string errors = fcu::describe_errors(status->error_code), override_ = fcu::describe_override(status->rc_override);
    std::printf("state:      %s, failsafe %s, offboard control %s, RC override %s, errors %s\n", status->armed ? "armed" : "disarmed",
                status->failsafe ? "ON" : "off", status->offboard ? "active" : "inactive", override_.empty() ? "none" : override_.c_str(),
                errors.empty() ? "none" : errors.c_str());
    const std::string problems = fcu::arming_problems(status->armed != 0, status->error_code);
    if (!problems.empty()) std::printf("            %s\n", problems.c_str());
  } else {
    std::printf("state:      (no ROSFLIGHT_STATUS within %.1f s)\n", samples / rate + std::max(timeout, 1.0));
  }
  const fcu::TimeSync::RttStats rtt = ts.rtt_stats();
  if (rtt.count == 0) {
    std::printf("round trip: no TIMESYNC answer to %d requests (%llu slower than 50 ms)\n", sent,
                static_cast<unsigned long long>(ts.rejected()));
    return 1;
  }
  std::printf(
      "round trip: p50 %.3f ms, p99 %.3f ms, max %.3f ms (TIMESYNC, %zu of %d requests answered within 50 ms); FCU clock - "
      "companion clock %.6f s\n",
      rtt.p50 * 1e-6, rtt.p99 * 1e-6, rtt.max * 1e-6, rtt.count, sent, ts.offset() * 1e-9);
  return status ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tern fcu: the firmware parameters, calibrations and state of a ROSflight flight-control unit"};
  app.require_subcommand(1);
  fcu::LinkOptions o;
  bool udp = false;
  double timeout = 1.0;
  app.add_option("--device", o.device, "serial device of the FCU")->capture_default_str();
  app.add_option("--baud", o.baud, "baud rate")->capture_default_str();
  app.add_flag("--udp", udp, "UDP (ROSflight SIL) instead of a serial port");
  app.add_option("--udp-host", o.udp_host, "UDP address")->capture_default_str();
  app.add_option("--udp-bind-port", o.udp_bind_port, "our UDP port")->capture_default_str();
  app.add_option("--udp-remote-port", o.udp_remote_port, "the FCU's UDP port")->capture_default_str();
  app.add_option("--timeout", timeout, "seconds to wait for each answer")->capture_default_str();
  auto* param = app.add_subcommand("param", "list, get or set firmware parameters");
  param->require_subcommand(1);
  auto* list = param->add_subcommand("list", "print every parameter: name value type");
  auto* get = param->add_subcommand("get", "print one parameter's value");
  std::string name, value;
  get->add_option("name", name, "parameter name (at most 16 characters)")->required();
  auto* set = param->add_subcommand("set", "set a parameter (in RAM; --write saves it)");
  set->add_option("name", name, "parameter name")->required();
  set->add_option("value", value, "new value")->required();
  bool write = false;
  set->add_flag("--write", write, "save every parameter to the FCU's flash afterwards (ROSFLIGHT_CMD_WRITE_PARAMS)");
  auto* write_cmd = param->add_subcommand("write", "save every parameter to the FCU's flash");
  auto* calibrate = app.add_subcommand("calibrate", "run a calibration on the FCU (disarmed; save it with `param write`)");
  std::string what;
  calibrate->add_option("what", what, "imu (accelerometer and gyro: level and still), gyro, baro, airspeed (pitot covered)")
      ->required()
      ->check(CLI::IsMember({"imu", "gyro", "baro", "airspeed"}));
  auto* status = app.add_subcommand("status", "the firmware's version, arming, failsafe, errors and the link's TIMESYNC round trip");
  int rtt_samples = 50;
  double rtt_rate = 10.0;
  status->add_option("--samples", rtt_samples, "TIMESYNC round trips to measure")->check(CLI::Range(1, 1000000))->capture_default_str();
  status->add_option("--rate", rtt_rate, "TIMESYNC requests per second (fcu_serial's timesync_rate: 10)")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (udp) o.kind = fcu::LinkOptions::Kind::udp;

  try {
    Client c(o);
    if (!c.find_target(std::max(timeout, 2.0))) {
      std::cerr << "tern fcu: nothing from an FCU on " << o.describe() << " within " << std::max(timeout, 2.0) << " s\n";
      return 1;
    }
    if (status->parsed()) return run_status(c, rtt_samples, rtt_rate, timeout);
    if (calibrate->parsed()) return run_calibration(c, what, timeout);
    if (write_cmd->parsed()) return command(c, fcu::RosflightCmd::write_params, timeout) ? 0 : 1;
    if (list->parsed()) {
      std::map<std::uint16_t, mav::ParamValue> table;
      std::optional<std::uint16_t> count;
      mav::ParamRequestList r;
      r.target_system = c.target;
      r.target_component = 1;
      c.send(r);
      auto take = [&](const mav::Message& m, std::int64_t& deadline) {
        if (const auto* v = std::get_if<mav::ParamValue>(&m)) {
          table[v->param_index] = *v;
          count = v->param_count;
          deadline = fcu::steady_ns() + static_cast<std::int64_t>(timeout * 1e9);  // progress: wait on
        }
        return count && table.size() >= *count;
      };
      c.collect(timeout, take);
      for (int round = 0; round < 3 && count && table.size() < *count; ++round) {  // ask again for the missing ones
        for (std::uint16_t i = 0; i < *count; ++i) {
          if (table.count(i)) continue;
          mav::ParamRequestRead rr;
          rr.target_system = c.target;
          rr.target_component = 1;
          rr.param_index = static_cast<std::int16_t>(i);
          c.send(rr);
        }
        c.collect(timeout, take);
      }
      if (!count) {
        std::cerr << "tern fcu: no parameters from the FCU on " << o.describe() << " within " << timeout << " s\n";
        return 1;
      }
      for (const auto& [i, v] : table)
        std::printf("%-16s %14s  %s\n", mav::to_string(v.param_id).c_str(), format_value(v).c_str(), type_name(v.param_type));
      if (table.size() < *count) {
        std::cerr << "tern fcu: got " << table.size() << " of " << *count << " parameters\n";
        return 1;
      }
      return 0;
    }
    if (name.size() > 16) {
      std::cerr << "tern fcu: parameter name '" << name << "' is longer than 16 characters\n";
      return 2;
    }
    const auto cur = read_param(c, name, timeout);
    if (!cur) {
      std::cerr << "tern fcu: the FCU on " << o.describe() << " has no parameter " << name << " (or did not answer)\n";
      return 1;
    }
    if (get->parsed()) {
      std::printf("%s\n", format_value(*cur).c_str());
      return 0;
    }
    double v = 0;
    try {
      std::size_t used = 0;
      v = std::stod(value, &used);
      if (used != value.size() || !std::isfinite(v)) throw std::invalid_argument(value);
    } catch (const std::exception&) {
      std::cerr << "tern fcu: value '" << value << "' for " << name << " is not a number\n";
      return 2;
    }
    if (cur->param_type != fcu::kParamReal32 && v != std::floor(v)) {
      std::cerr << "tern fcu: " << name << " is an integer parameter (" << type_name(cur->param_type) << "), got " << value << "\n";
      return 2;
    }
    mav::ParamSet ps;
    ps.target_system = c.target;
    ps.target_component = 1;
    ps.param_id = mav::to_chars<16>(name);
    ps.param_type = cur->param_type;
    ps.param_value = fcu::param_wire(v, cur->param_type);
    // The firmware echoes only a change and ignores the other type: read the value back.
    c.send(ps);
    const auto back = read_param(c, name, timeout);
    if (!back || back->param_value != ps.param_value || back->param_type != ps.param_type) {
      std::cerr << "tern fcu: the FCU did not take " << name << " = " << value << " (reads "
                << (back ? format_value(*back) : std::string("nothing")) << ")\n";
      return 1;
    }
    const auto& echo = back;
    std::printf("%s = %s\n", name.c_str(), format_value(*echo).c_str());
    if (write && !command(c, fcu::RosflightCmd::write_params, timeout)) return 1;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "tern fcu: " << e.what() << "\n";
    return 1;
  }
}
