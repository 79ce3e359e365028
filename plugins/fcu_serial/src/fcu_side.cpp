// fcu_side.cpp: see tern_fcu_serial/fcu_side.hpp.
#include "tern_fcu_serial/fcu_side.hpp"

#include <bit>
#include <cmath>

#include "tern_fcu_serial/timesync.hpp"

namespace tern::fcu {

double param_number(float wire, std::uint8_t type) {
  if (type == kParamInt32) return static_cast<double>(std::bit_cast<std::int32_t>(wire));
  return static_cast<double>(wire);
}

float param_wire(double v, std::uint8_t type) {
  if (type == kParamInt32) return std::bit_cast<float>(static_cast<std::int32_t>(std::lround(v)));
  return static_cast<float>(v);
}

FcuSide::FcuSide(std::optional<firmware::Params> flash, std::string version)
    : fw_(flash), stored_(flash.value_or(firmware::Params{})), version_(std::move(version)) {}

// MavlinkAdapter::send_param_value_int/float: component 0, the value's type, PARAMS_COUNT.
void FcuSide::send_param(std::size_t i, std::vector<std::uint8_t>& out) {
  const firmware::Param& p = fw_.params().at(i);
  mavlink::ParamValue v;
  v.param_id = mavlink::to_chars<16>(p.name);
  v.param_type = static_cast<std::uint8_t>(p.type);
  v.param_value = p.type == firmware::ParamType::int32 ? std::bit_cast<float>(p.i) : p.f;
  v.param_count = static_cast<std::uint16_t>(fw_.params().size());
  v.param_index = static_cast<std::uint16_t>(i);
  enc_.append_as(v, out, sysid(), 0);
}

// CommManager::param_set_int_callback / param_set_float_callback (via the adapter's type
// switch): the parameter must exist and have the type the request says.
void FcuSide::param_set(const mavlink::ParamSet& s) {
  if (s.target_system != sysid()) return;
  const std::string name = mavlink::to_string(s.param_id);
  const auto i = fw_.params().find(name);
  if (!i || static_cast<std::uint8_t>(fw_.params().at(*i).type) != s.param_type) return;
  if (s.param_type == kParamInt32)
    fw_.params().set_int(*i, std::bit_cast<std::int32_t>(s.param_value));
  else
    fw_.params().set_float(*i, s.param_value);
}

// CommManager::command_callback (refused while armed) and the adapter's unknown-command ack.
void FcuSide::command(const mavlink::RosflightCmd& c, std::uint8_t from_sysid, std::vector<std::uint8_t>& out) {
  mavlink::RosflightCmdAck ack;
  ack.command = c.command;
  if (c.command > static_cast<std::uint8_t>(RosflightCmd::send_version)) {
    ack.success = 0;  // ROSFLIGHT_CMD_FAILED, sent under the sender's system id
    enc_.append_as(ack, out, from_sysid, kFirmwareComponent);
    return;
  }
  bool ok = !fw_.armed();
  if (ok) {
    switch (static_cast<RosflightCmd>(c.command)) {
      case RosflightCmd::read_params: fw_.params() = stored_; break;
      case RosflightCmd::write_params:
        stored_ = fw_.params();
        ++writes_;
        break;
      case RosflightCmd::set_param_defaults: fw_.params().set_defaults(); break;
      case RosflightCmd::accel_calibration: ok = fw_.start_imu_calibration(); break;
      case RosflightCmd::gyro_calibration: ok = fw_.start_gyro_calibration(); break;
      case RosflightCmd::baro_calibration: ok = fw_.start_baro_calibration(); break;
      case RosflightCmd::airspeed_calibration: ok = fw_.start_airspeed_calibration(); break;
      case RosflightCmd::reboot:
      case RosflightCmd::reboot_to_bootloader: reboot_ = true; break;
      case RosflightCmd::send_version: {
        mavlink::RosflightVersion v;
        v.version = mavlink::to_chars<50>(version_);
        send(v, out);
        break;
      }
      default: break;  // RC_CALIBRATION: equilibrium torques of the attitude controller (not emulated)
    }
  }
  ack.success = ok ? 1 : 0;
  send(ack, out);
}

void FcuSide::handle(const mavlink::Frame& f, std::int64_t fcu_ns, std::vector<std::uint8_t>& out) {
  const auto m = mavlink::decode(f);
  if (!m) return;
  if (const auto* c = std::get_if<mavlink::OffboardControl>(&*m)) {
    std::array<float, 10> u{};
    for (std::size_t i = 0; i < 10; ++i) u[i] = c->u[i];
    fw_.offboard(c->mode, u, c->ignore, fcu_ns);
    ++commands_;
  } else if (std::holds_alternative<mavlink::Heartbeat>(*m)) {
    connected_ = true;  // CommManager::heartbeat_callback
  } else if (const auto* t = std::get_if<mavlink::Timesync>(&*m)) {
    if (auto a = TimeSync::respond(*t, fcu_ns / 1000 * 1000)) send(*a, out);
  } else if (const auto* l = std::get_if<mavlink::ParamRequestList>(&*m)) {
    if (l->target_system == sysid()) list_next_ = 0;
  } else if (const auto* r = std::get_if<mavlink::ParamRequestRead>(&*m)) {
    if (r->target_system != sysid()) return;
    const auto i = r->param_index < 0 ? fw_.params().find(mavlink::to_string(r->param_id))
                                      : std::optional<std::size_t>(static_cast<std::size_t>(r->param_index));
    if (i && *i < fw_.params().size()) send_param(*i, out);
  } else if (const auto* s = std::get_if<mavlink::ParamSet>(&*m)) {
    param_set(*s);
  } else if (const auto* c = std::get_if<mavlink::RosflightCmd>(&*m)) {
    command(*c, f.sysid, out);
  }
  stream_echoes(out);
}

void FcuSide::stream_echoes(std::vector<std::uint8_t>& out) {
  for (std::size_t i : fw_.params().take_changes()) {
    fw_.param_changed(fw_.params().at(i).name);
    send_param(i, out);  // Params::set_param_*: CommManager::send_param_value on a change
  }
}

// CommManager::log / send_log_message: the text as vsnprintf into LOG_MSG_SIZE (50) leaves it,
// at most 49 characters.
void FcuSide::send_log(const firmware::LogLine& line, std::uint8_t system_id, std::vector<std::uint8_t>& out) {
  mavlink::Statustext st;
  st.severity = line.severity;
  st.text = mavlink::to_chars<50>(line.text.substr(0, 49));
  enc_.append_as(st, out, system_id, kFirmwareComponent);
}

void FcuSide::stream(std::int64_t fcu_ns, std::vector<std::uint8_t>& out) {
  stream_echoes(out);
  if (fw_.take_status_request()) send(status(), out);
  if (list_next_ < fw_.params().size()) send_param(list_next_++, out);
  // CommManager::log_message: once a HEARTBEAT came, a line goes out at once; before, it waits
  // in a buffer of LOG_BUF_SIZE (25, the oldest overwritten)
  for (const auto& line : fw_.take_log()) {
    if (connected_) {
      send_log(line, sysid(), out);
    } else {
      held_log_.push_back(line);
      if (held_log_.size() > kLogBufferSize) held_log_.erase(held_log_.begin());
    }
  }
  // CommManager::send_buffered_log_messages: one held line a loop, sent with clock_micros() where
  // the system id belongs (the firmware passes the time as send_log_message's system_id)
  if (connected_ && !held_log_.empty()) {
    send_log(held_log_.front(), static_cast<std::uint8_t>(fcu_ns / 1000), out);
    held_log_.erase(held_log_.begin());
  }
}

mavlink::RosflightStatus FcuSide::status() const {
  mavlink::RosflightStatus s;
  s.armed = fw_.armed() ? 1 : 0;
  s.failsafe = fw_.failsafe() ? 1 : 0;
  s.rc_override = fw_.rc_override();
  s.offboard = fw_.offboard_active() ? 1 : 0;
  s.error_code = static_cast<std::uint8_t>(fw_.error_codes());  // uint8_t in the message
  s.control_mode = 0;                                           // FIXED_WING: MODE_PASS_THROUGH (CommManager::send_status)
  s.num_errors = 0;
  s.loop_time_us = static_cast<std::int16_t>(loop_time_us_);
  return s;
}

mavlink::Heartbeat FcuSide::heartbeat() const {
  mavlink::Heartbeat h;
  h.type = fw_.params().get_int("FIXED_WING") ? 1 : 2;  // MAV_TYPE_FIXED_WING or MAV_TYPE_QUADROTOR
  h.autopilot = 0;
  h.base_mode = 0;
  h.custom_mode = 0;
  h.system_status = 0;
  h.mavlink_version = 3;
  return h;
}

}  // namespace tern::fcu
