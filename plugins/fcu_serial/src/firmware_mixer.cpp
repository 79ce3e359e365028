// firmware_mixer.cpp: the fixed-wing mixers of the emulated firmware, after include/mixer.h
// (fixedwing_mixing, fixedwing_inverted_vtail_mixing) and src/mixer.cpp (Mixer::init_mixing,
// mix_fixedwing, mix_output). See firmware.hpp.
#include "tern_fcu_serial/firmware.hpp"

namespace tern::fcu::firmware {

namespace {
constexpr int kFixedwing = 9, kInvertedVtail = 10;  // mixer.h mixer_type_t
}  // namespace

// Mixer::init_mixing: PRIMARY_MIXER selects a canned mixer; an invalid choice sets
// ERROR_INVALID_MIXER and the mixer writes nothing. Inputs (rows) are the muxed channels
// Fx Fy Fz Qx Qy Qz; outputs 0-2 servos, 4 the motor. SECONDARY_MIXER 255 mirrors the primary.
// Its log lines, as the firmware says them (severity: 3 error, 4 warning, 6 info).
void Firmware::init_mixing() {
  clear_error(kErrorInvalidMixer);
  const std::int32_t choice = params_.get_int("PRIMARY_MIXER");
  mix_ = {};
  output_type_.fill('A');
  mixer_valid_ = choice == kFixedwing || choice == kInvertedVtail;
  if (!mixer_valid_) {
    if (choice >= 0 && choice <= 11)
      log(3, "emulator: PRIMARY_MIXER " + std::to_string(choice) + " is not emulated (fixed wing: 9 or 10)");
    else
      log(3, "Invalid mixer choice for primary mixer");
    set_error(kErrorInvalidMixer);
  } else {
    output_type_[0] = output_type_[1] = output_type_[2] = 'S';
    output_type_[4] = 'M';
    mix_[0][4] = 1.0f;  // Fx -> motor
    mix_[3][0] = 1.0f;  // Qx -> output 0 (aileron)
    if (choice == kFixedwing) {
      mix_[4][1] = 1.0f;  // Qy -> output 1 (elevator)
      mix_[5][2] = 1.0f;  // Qz -> output 2 (rudder)
    } else {              // inverted V-tail: left and right ruddervators
      mix_[4][1] = -0.5f;
      mix_[4][2] = 0.5f;
      mix_[5][1] = 0.5f;
      mix_[5][2] = 0.5f;
    }
    if (const std::int32_t axis = params_.get_int("RC_F_AXIS"); axis != 0) {
      log(4, "PRIMARY_MIXER=" + std::to_string(choice) + " but RC_F_AXIS=" + std::to_string(static_cast<unsigned>(axis)) + ", which");
      log(4, "will cause issues (check docs). Is this correct?");
    }
  }
  const std::int32_t secondary = params_.get_int("SECONDARY_MIXER");
  if (secondary < 0 || secondary > 11) {  // NUM_MIXERS and beyond, as the firmware's unsigned enum reads them
    log(6, "Invalid mixer selected for secondary mixer!");
    log(6, "Secondary mixer defaulting to primary!");
  } else {
    log(4, "emulator: SECONDARY_MIXER other than 255 is not emulated (uses the primary)");
  }
  raw_.fill(0.0f);
}

// Mixer::mix_output with mix_fixedwing: Controller::run passes the muxed values through
// (plus X/Y/Z_EQ_TORQUE), REV_* reverse Qx, Qy, Qz, then a servo is clamped to -1..1 and
// written as 0.5 + 0.5 u, a motor to 0..1 (MOTOR_IDLE_THR with ARM_SPIN_MOTORS), 0 disarmed.
void Firmware::mix_output() {
  if (!mixer_valid_) return;
  std::array<float, 10> u{};
  for (std::size_t i = 0; i < 10; ++i) u[i] = combined_[i].value;
  u[3] += params_.get_float("X_EQ_TORQUE");
  u[4] += params_.get_float("Y_EQ_TORQUE");
  u[5] += params_.get_float("Z_EQ_TORQUE");
  if (params_.get_int("REV_AILERON")) u[3] = -u[3];
  if (params_.get_int("REV_ELEVATOR")) u[4] = -u[4];
  if (params_.get_int("REV_RUDDER")) u[5] = -u[5];
  for (std::size_t o = 0; o < 10; ++o) {
    if (output_type_[o] == 'A') continue;  // AUX outputs carry aux commands (none here)
    float v = 0.0f;
    for (std::size_t j = 0; j < 10; ++j) v += u[j] * mix_[j][o];
    if (output_type_[o] == 'S') {
      v = v > 1.0f ? 1.0f : (v < -1.0f ? -1.0f : v);
      raw_[o] = 0.5f * v + 0.5f;
    } else if (!armed_) {
      raw_[o] = 0.0f;
    } else {
      const float idle = params_.get_float("MOTOR_IDLE_THR");
      if (v > 1.0f)
        v = 1.0f;
      else if (v < idle && params_.get_int("ARM_SPIN_MOTORS"))
        v = idle;
      else if (v < 0.0f)
        v = 0.0f;
      raw_[o] = v;
    }
  }
}

}  // namespace tern::fcu::firmware
