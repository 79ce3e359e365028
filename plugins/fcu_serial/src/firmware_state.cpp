// firmware_state.cpp: boot, arming, errors and failsafe of the emulated firmware, after
// src/state_manager.cpp (StateManager) and src/rosflight.cpp (ROSflight::init). See firmware.hpp.
#include "tern_fcu_serial/firmware.hpp"

namespace tern::fcu::firmware {

// ROSflight::init: StateManager::init (INIT -> PREFLIGHT), Params::init (no readable flash: the
// defaults, said as a warning), Mixer::init (init_mixing: ERROR_INVALID_MIXER unless
// PRIMARY_MIXER is valid), RC::init (init_switches' log lines), Sensors::init (init_imu:
// ERROR_UNCALIBRATED_IMU while every stored bias is 0), CommandManager::init (init_failsafe).
// Boots disarmed.
Firmware::Firmware(std::optional<Params> flash) : params_(flash.value_or(Params{})) {
  set_event(Event::initialized, 0);
  if (!flash) log(4, "Unable to load parameters; using default values");
  init_mixing();
  log_switches();
  check_imu_calibrated();
  init_failsafe();
  params_.take_changes();  // boot-time writes are not echoed to anyone
}

void Firmware::log(std::uint8_t severity, std::string text) { log_.push_back({severity, std::move(text)}); }

std::vector<LogLine> Firmware::take_log() {
  std::vector<LogLine> l;
  l.swap(log_);
  return l;
}

bool Firmware::take_status_request() {
  const bool r = status_request_;
  status_request_ = false;
  return r;
}

// StateManager::set_error / clear_error: each change is run through the FSM.
void Firmware::set_error(std::uint16_t e) {
  errors_ |= e;
  process_errors(0);
}

void Firmware::clear_error(std::uint16_t e) {
  if (!(errors_ & e)) return;
  errors_ &= static_cast<std::uint16_t>(~e);
  process_errors(0);
  status_request_ = true;
}

void Firmware::process_errors(std::int64_t now) { set_event(errors_ ? Event::error : Event::no_error, now); }

// CommandManager::init_failsafe (at boot and when FIXED_WING or FAILSAFE_THR change): a
// multirotor's FAILSAFE_THR must lie in 0..1, else ERROR_INVALID_FAILSAFE (the firmware's
// defaults, FIXED_WING 0 and FAILSAFE_THR -1, have it); a fixed wing's failsafe throttle is 0.
void Firmware::init_failsafe() {
  const float thr = params_.get_float("FAILSAFE_THR");
  if (!params_.get_int("FIXED_WING") && (thr < 0.0f || thr > 1.0f))
    set_error(kErrorInvalidFailsafe);
  else
    clear_error(kErrorInvalidFailsafe);
  const std::int32_t axis = params_.get_int("RC_F_AXIS");
  if (axis < 0 || axis > 2) log(4, "Invalid RC F axis. Defaulting to z-axis.");
}

// StateManager::set_event, FSM_STATE_ERROR / EVENT_REQUEST_ARM: the reasons, when the last ones
// are more than a second old (in whole ms: 1 s and one RC frame apart at 50 Hz).
void Firmware::refuse_arm(std::int64_t now) {
  const std::int64_t ms = now / 1'000'000;
  if (ms <= next_arm_error_ms_) return;
  const std::pair<std::uint16_t, const char*> why[] = {{kErrorInvalidMixer, "Unable to arm: Invalid mixer"},
                                                       {kErrorImuNotResponding, "Unable to arm: IMU not responding"},
                                                       {kErrorRcLost, "Unable to arm: RC signal lost"},
                                                       {kErrorUnhealthyEstimator, "Unable to arm: Unhealthy estimator"},
                                                       {kErrorTimeGoingBackwards, "Unable to arm: Time going backwards"},
                                                       {kErrorUncalibratedImu, "Unable to arm: IMU not calibrated"},
                                                       {kErrorInvalidFailsafe, "Unable to arm: Invalid failsafe setting"}};
  for (const auto& [bit, text] : why)
    if (errors_ & bit) log(3, text);
  next_arm_error_ms_ = ms + 1000;
}

void Firmware::set_event(Event e, std::int64_t now) {
  const Fsm start = fsm_;
  const std::uint16_t start_errors = errors_;
  switch (fsm_) {
    case Fsm::init:
      if (e == Event::initialized) fsm_ = Fsm::preflight;
      break;
    case Fsm::preflight:
      if (e == Event::rc_found) {
        clear_error(kErrorRcLost);
        failsafe_ = false;
      } else if (e == Event::rc_lost) {
        set_error(kErrorRcLost);
      } else if (e == Event::error) {
        error_ = true;
        fsm_ = Fsm::error;
      } else if (e == Event::request_arm) {
        // low RC throttle, and TAKE_MIN_THR or the throttle-override switch
        if (stick_[3] >= params_.get_float("RC_ARM_THRESHOLD")) {
          log(3, "Cannot arm with RC throttle high");
        } else if (!params_.get_int("TAKE_MIN_THR") && !switch_on("RC_THR_OVRD_CHN")) {
          log(3, "RC throttle override must be active to arm");
        } else if (params_.get_int("ARM_CAL_GYRO")) {
          fsm_ = Fsm::calibrating;
          start_gyro_calibration();
        } else {
          armed_ = true;
          status_request_ = true;
          fsm_ = Fsm::armed;
        }
      }
      break;
    case Fsm::error:
      if (e == Event::rc_lost) {
        set_error(kErrorRcLost);
      } else if (e == Event::rc_found) {
        clear_error(kErrorRcLost);
        failsafe_ = false;
      } else if (e == Event::no_error) {
        error_ = false;
        fsm_ = Fsm::preflight;
      } else if (e == Event::request_arm) {
        refuse_arm(now);
      }
      break;
    case Fsm::calibrating:
      if (e == Event::cal_done) {
        armed_ = true;
        fsm_ = Fsm::armed;
      } else if (e == Event::cal_failed) {
        fsm_ = Fsm::preflight;
      } else if (e == Event::rc_lost) {
        set_error(kErrorRcLost);
      } else if (e == Event::error) {
        fsm_ = Fsm::error;
        error_ = true;
      } else if (e == Event::no_error) {
        error_ = false;
      }
      break;
    case Fsm::armed:
      if (e == Event::rc_lost) {  // armed and the transmitter lost: failsafe
        failsafe_ = true;
        fsm_ = Fsm::failsafe;
        set_error(kErrorRcLost);
        status_request_ = true;
      } else if (e == Event::request_disarm) {
        armed_ = false;
        fsm_ = error_ ? Fsm::error : Fsm::preflight;
      } else if (e == Event::error) {
        error_ = true;
      } else if (e == Event::no_error) {
        error_ = false;
      }
      break;
    case Fsm::failsafe:
      if (e == Event::error) {
        error_ = true;
      } else if (e == Event::request_disarm) {
        armed_ = false;
        fsm_ = Fsm::error;
      } else if (e == Event::rc_found) {
        failsafe_ = false;
        fsm_ = Fsm::armed;
        clear_error(kErrorRcLost);
      }
      break;
  }
  if (start != fsm_ || start_errors != errors_) status_request_ = true;
}

}  // namespace tern::fcu::firmware
