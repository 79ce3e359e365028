// firmware_params.cpp: the firmware's parameter table and its set rules (see firmware.hpp).
#include <stdexcept>

#include "tern_fcu_serial/firmware.hpp"

namespace tern::fcu::firmware {

namespace {
Param i32(const char* n, std::int32_t v) { return Param{n, ParamType::int32, v, 0.0f}; }
Param f32(const char* n, float v) { return Param{n, ParamType::real32, 0, v}; }
}  // namespace

// Names, types and defaults of src/param.cpp Params::set_defaults (only those the emulator
// uses; the firmware's table also holds the PID gains, estimator, battery and mixer-matrix
// parameters). Note the defaults: PRIMARY_MIXER invalid (255), TAKE_MIN_THR 1, RC_F_AXIS 2 (Z),
// FIXED_WING 0: a fixed wing must be configured (rosflight_sim's fixedwing_firmware.yaml).
std::vector<Param> Params::defaults() {
  return {i32("SYS_ID", 1),
          i32("BAUD_RATE", 921600),
          i32("FIXED_WING", 0),
          i32("PRIMARY_MIXER", 255),
          i32("SECONDARY_MIXER", 255),
          i32("REV_ELEVATOR", 0),
          i32("REV_AILERON", 0),
          i32("REV_RUDDER", 0),
          f32("MOTOR_IDLE_THR", 0.1f),
          f32("FAILSAFE_THR", -1.0f),
          i32("ARM_SPIN_MOTORS", 1),
          i32("ARM_CAL_GYRO", 0),
          i32("RC_TYPE", 0),
          i32("RC_X_CHN", 0),
          i32("RC_Y_CHN", 1),
          i32("RC_Z_CHN", 3),
          i32("RC_F_CHN", 2),
          i32("RC_F_AXIS", 2),
          i32("RC_ATT_OVRD_CHN", 4),
          i32("RC_THR_OVRD_CHN", 4),
          i32("RC_ATT_CTRL_CHN", -1),
          i32("RC_ARM_CHN", -1),
          i32("RC_NUM_CHN", 6),
          i32("SWITCH_5_DIR", 1),
          i32("SWITCH_6_DIR", 1),
          i32("SWITCH_7_DIR", 1),
          i32("SWITCH_8_DIR", 1),
          f32("RC_OVRD_DEV", 0.1f),
          i32("RC_OVRD_LAG_T", 1000),
          i32("TAKE_MIN_THR", 1),
          f32("RC_MAX_THR", 0.7f),
          f32("RC_ARM_THRESHOLD", 0.15f),
          i32("OFFBOARD_TIMEOUT", 100),
          f32("X_EQ_TORQUE", 0.0f),
          f32("Y_EQ_TORQUE", 0.0f),
          f32("Z_EQ_TORQUE", 0.0f),
          f32("GYRO_X_BIAS", 0.0f),
          f32("GYRO_Y_BIAS", 0.0f),
          f32("GYRO_Z_BIAS", 0.0f),
          f32("ACC_X_BIAS", 0.0f),
          f32("ACC_Y_BIAS", 0.0f),
          f32("ACC_Z_BIAS", 0.0f),
          f32("BARO_BIAS", 0.0f),
          f32("GROUND_LEVEL", 1387.0f),
          f32("DIFF_PRESS_BIAS", 0.0f)};
}

Params::Params() : table_(defaults()) {}

std::optional<std::size_t> Params::find(std::string_view name) const {
  for (std::size_t i = 0; i < table_.size(); ++i)
    if (table_[i].name == name) return i;
  return std::nullopt;
}

std::size_t Params::index(std::string_view name) const {
  const auto i = find(name);
  if (!i) throw std::out_of_range("firmware parameter " + std::string(name) + " is not emulated");
  return *i;
}

const Param& Params::get(std::string_view name, ParamType t) const {
  const Param& p = table_[index(name)];
  if (p.type != t) throw std::out_of_range("firmware parameter " + p.name + " has the other type");
  return p;
}

std::int32_t Params::get_int(std::string_view name) const { return get(name, ParamType::int32).i; }
float Params::get_float(std::string_view name) const { return get(name, ParamType::real32).f; }

// Params::set_param_int / set_param_float: a value equal to the current one is no change (no
// callback, no PARAM_VALUE).
bool Params::set_int(std::size_t i, std::int32_t v) {
  Param& p = table_.at(i);
  if (p.type != ParamType::int32) throw std::out_of_range("firmware parameter " + p.name + " is a float");
  if (p.i == v) return false;
  p.i = v;
  changes_.push_back(i);
  return true;
}

bool Params::set_float(std::size_t i, float v) {
  Param& p = table_.at(i);
  if (p.type != ParamType::real32) throw std::out_of_range("firmware parameter " + p.name + " is an int32");
  if (p.f == v) return false;
  p.f = v;
  changes_.push_back(i);
  return true;
}

bool Params::set_int(std::string_view name, std::int32_t v) { return set_int(index(name), v); }
bool Params::set_float(std::string_view name, float v) { return set_float(index(name), v); }

// Params::set_defaults writes through init_param_int/float: no PARAM_VALUE is sent.
void Params::set_defaults() { table_ = defaults(); }

std::vector<std::size_t> Params::take_changes() {
  std::vector<std::size_t> c;
  c.swap(changes_);
  return c;
}

}  // namespace tern::fcu::firmware
