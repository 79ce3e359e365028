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

FcuSide::FcuSide(std::vector<FcuParam> params, std::string version, std::uint8_t sysid, std::uint8_t compid)
    : params_(std::move(params)), defaults_(params_), version_(std::move(version)), enc_(sysid, compid) {}

std::vector<FcuParam> FcuSide::default_params() {
  auto i = [](const char* n, int v) { return FcuParam{n, param_wire(v, kParamInt32), kParamInt32}; };
  auto f = [](const char* n, double v) { return FcuParam{n, param_wire(v, kParamReal32), kParamReal32}; };
  // fixedwing_firmware.yaml (rosflight_sim, BSD-3-Clause) and ROSflight's stream rates.
  return {i("ARM_SPIN_MOTORS", 0), f("MOTOR_IDLE_THR", 0.1), i("RC_ARM_CHN", 4),     i("FIXED_WING", 1),
          i("PRIMARY_MIXER", 10),  i("REV_ELEVATOR", 1),     i("REV_AILERON", 0),    i("REV_RUDDER", 0),
          i("ARM_CAL_GYRO", 0),    i("RC_THR_OVRD_CHN", 5),  i("RC_ATT_OVRD_CHN", 5), i("RC_ATT_CTRL_CHN", 8),
          i("TAKE_MIN_THR", 0),    f("RC_OVRD_DEV", 1.0),    i("RC_NUM_CHN", 8),     i("RC_F_AXIS", 0),
          i("BAUD_RATE", 921600),  i("STRM_IMU", 400),       i("STRM_MAG", 50),      i("STRM_BARO", 100),
          i("STRM_AIRSPEED", 100), i("STRM_GNSS", 10),       i("STRM_RC", 50),       i("STRM_STATUS", 10),
          f("OFFBOARD_TIMEOUT", 100)};
}

void FcuSide::send_param(std::size_t i, std::vector<std::uint8_t>& out) {
  mavlink::ParamValue v;
  v.param_id = mavlink::to_chars<16>(params_[i].name);
  v.param_value = params_[i].value;
  v.param_type = params_[i].type;
  v.param_count = static_cast<std::uint16_t>(params_.size());
  v.param_index = static_cast<std::uint16_t>(i);
  enc_.append(v, out);
}

void FcuSide::handle(const mavlink::Frame& f, std::int64_t fcu_ns, std::vector<std::uint8_t>& out) {
  const auto m = mavlink::decode(f);
  if (!m) return;
  if (const auto* c = std::get_if<mavlink::OffboardControl>(&*m)) {
    cmd_ = *c;
    ++commands_;
    last_cmd_ns_ = fcu_ns;
  } else if (const auto* t = std::get_if<mavlink::Timesync>(&*m)) {
    if (auto a = TimeSync::respond(*t, fcu_ns)) enc_.append(*a, out);
  } else if (std::holds_alternative<mavlink::ParamRequestList>(*m)) {
    for (std::size_t i = 0; i < params_.size(); ++i) send_param(i, out);
  } else if (const auto* r = std::get_if<mavlink::ParamRequestRead>(&*m)) {
    if (r->param_index >= 0 && static_cast<std::size_t>(r->param_index) < params_.size()) {
      send_param(static_cast<std::size_t>(r->param_index), out);
    } else {
      const std::string name = mavlink::to_string(r->param_id);
      for (std::size_t i = 0; i < params_.size(); ++i)
        if (params_[i].name == name) send_param(i, out);
    }
  } else if (const auto* s = std::get_if<mavlink::ParamSet>(&*m)) {
    const std::string name = mavlink::to_string(s->param_id);
    for (std::size_t i = 0; i < params_.size(); ++i) {
      if (params_[i].name != name) continue;
      // ROSflight keeps the parameter's own type; a value sent with another type is converted.
      params_[i].value = param_wire(param_number(s->param_value, s->param_type), params_[i].type);
      send_param(i, out);
    }
  } else if (const auto* c = std::get_if<mavlink::RosflightCmd>(&*m)) {
    mavlink::RosflightCmdAck ack;
    ack.command = c->command;
    ack.success = 1;
    switch (static_cast<RosflightCmd>(c->command)) {
      case RosflightCmd::send_version: {
        mavlink::RosflightVersion v;
        v.version = mavlink::to_chars<50>(version_);
        enc_.append(v, out);
        break;
      }
      case RosflightCmd::set_param_defaults: params_ = defaults_; break;
      case RosflightCmd::write_params: ++writes_; break;
      case RosflightCmd::reboot: reboot_ = true; break;
      case RosflightCmd::read_params:
      case RosflightCmd::rc_calibration:
      case RosflightCmd::accel_calibration:
      case RosflightCmd::gyro_calibration:
      case RosflightCmd::baro_calibration:
      case RosflightCmd::airspeed_calibration:
      case RosflightCmd::reset_origin:
      case RosflightCmd::send_all_config_infos: break;
      default: ack.success = 0; break;
    }
    enc_.append(ack, out);
  }
}

}  // namespace tern::fcu
