// sil/sil_board.hpp: tern's software-in-the-loop board for the real ROSflight firmware: an
// implementation of the firmware's `Board` interface (rosflight_firmware
// include/interface/board.h) that the SIL loop (sil.hpp) fills with sim_aero's world.
//
// What a real board does and this one does instead:
// - Sensors: each *_read() hands the firmware the newest sample the loop put in since the last
//   read (true), or nothing (false), as a board's drivers do with their data-ready flags. The
//   structs are in the units board.h gives: IMU specific force m/s^2 and rates rad/s in the
//   board's axes (FRD), temperature K, timestamp us of the board clock; magnetometer flux T;
//   barometer and differential pressure Pa, K (the firmware computes altitude and IAS:
//   sensors.cpp correct_baro, correct_diff_pressure); GNSS the fix structure (lat/lon deg,
//   height MSL m, NED velocity m/s, accuracies m and m/s, Unix time, timestamp = time of
//   validity, us). No range finder, no battery monitor (sim_aero models neither): both false.
// - RC: one receiver frame per rc_read() as the loop delivers them (chan 0..1 = 1000..2000 us,
//   the firmware's scaling in rc.cpp; frameLost / failsafeActivated as an SBUS receiver's).
// - Time: the loop's simulated clock (microseconds since power-up); clock_delay() does not wait
//   (the firmware's only use is before a reboot, comm_manager.cpp command_callback).
// - Serial: a byte queue each way; the loop moves the bytes to and from the pseudo-terminal.
// - PWM: the last pwm_write() values (the mixer's raw outputs: servos 0..1, motors 0..1) and the
//   rates of pwm_init(); the loop turns them into surface and throttle commands.
// - Flash (memory_read/write): one file holding the firmware's parameter block as it writes it;
//   missing or of another size: read fails and the firmware takes its defaults (param.cpp init).
// - Backup memory (hard-fault data): kept in RAM, surviving an in-process reboot as a board's
//   backup SRAM survives a reset. LEDs: their states are kept (led0: armed, led1: heartbeat).
// - board_reset(): sets reboot_requested(); the loop boots the firmware again.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "board.h"

namespace tern::fcu::sil {

class SilBoard final : public rosflight_firmware::Board {
 public:
  /// flash_file: where the parameter block lives (created on the firmware's first write).
  explicit SilBoard(std::string flash_file);

  // ---- the loop's side ----
  void set_time_us(std::uint64_t t) { now_us_ = t; }
  void put_imu(const rosflight_firmware::ImuStruct& s) { imu_ = s; }
  void put_mag(const rosflight_firmware::MagStruct& s) { mag_ = s; }
  void put_baro(const rosflight_firmware::PressureStruct& s) { baro_ = s; }
  void put_diff_pressure(const rosflight_firmware::PressureStruct& s) { diff_ = s; }
  void put_gnss(const rosflight_firmware::GnssStruct& s) { gnss_ = s; }
  void put_rc(const rosflight_firmware::RcStruct& s) { rc_ = s; }
  /// Bytes from the companion, in arrival order.
  void receive_bytes(const std::uint8_t* p, std::size_t n) { rx_.insert(rx_.end(), p, p + n); }
  /// Everything the firmware wrote to the serial port since the last call.
  std::vector<std::uint8_t> take_sent();
  static constexpr std::size_t kOutputs = 14;  ///< Mixer::NUM_TOTAL_OUTPUTS
  const std::array<float, kOutputs>& pwm() const { return pwm_; }
  /// Rate of each output from pwm_init(), Hz (0: not initialised).
  const std::array<float, kOutputs>& pwm_rate() const { return pwm_rate_; }
  bool pwm_enabled() const { return pwm_enabled_; }
  bool reboot_requested() const { return reboot_; }
  void clear_reboot() { reboot_ = false; }
  bool armed_led() const { return led0_; }
  const std::string& flash_file() const { return flash_; }

  // ---- rosflight_firmware::Board ----
  void init_board() override {}
  void board_reset(bool bootloader) override;
  void sensors_init() override {}
  std::uint16_t sensors_errors_count() override { return 0; }
  std::uint16_t sensors_init_message_count() override { return 0; }
  bool sensors_init_message_good(std::uint16_t) override { return true; }
  std::uint16_t sensors_init_message(char* message, std::uint16_t size, std::uint16_t i) override;

  std::uint32_t clock_millis() override { return static_cast<std::uint32_t>(now_us_ / 1000); }
  std::uint64_t clock_micros() override { return now_us_; }
  void clock_delay(std::uint32_t) override {}

  void serial_init(std::uint32_t, std::uint32_t) override {}
  void serial_write(const std::uint8_t* src, std::size_t len, std::uint8_t qos) override;
  std::uint16_t serial_bytes_available() override;
  std::uint8_t serial_read() override;
  void serial_flush() override {}

  bool imu_read(rosflight_firmware::ImuStruct* imu) override { return take(imu_, imu); }
  bool mag_read(rosflight_firmware::MagStruct* mag) override { return take(mag_, mag); }
  bool baro_read(rosflight_firmware::PressureStruct* baro) override { return take(baro_, baro); }
  bool diff_pressure_read(rosflight_firmware::PressureStruct* diff) override { return take(diff_, diff); }
  bool range_read(rosflight_firmware::RangeStruct*) override { return false; }
  bool gnss_read(rosflight_firmware::GnssStruct* gnss) override { return take(gnss_, gnss); }
  bool battery_read(rosflight_firmware::BatteryStruct*) override { return false; }
  void battery_voltage_set_multiplier(double) override {}
  void battery_current_set_multiplier(double) override {}

  void rc_init(rc_type_t) override {}
  bool rc_read(rosflight_firmware::RcStruct* rc) override { return take(rc_, rc); }

  void pwm_init(const float* rate, std::uint32_t channels) override;
  void pwm_disable() override;
  void pwm_write(float* value, std::uint32_t channels) override;

  void memory_init() override {}
  bool memory_read(void* dest, std::size_t len) override;
  bool memory_write(const void* src, std::size_t len) override;

  void led0_on() override { led0_ = true; }
  void led0_off() override { led0_ = false; }
  void led0_toggle() override { led0_ = !led0_; }
  void led1_on() override { led1_ = true; }
  void led1_off() override { led1_ = false; }
  void led1_toggle() override { led1_ = !led1_; }

  void backup_memory_init() override {}
  bool backup_memory_read(void* dest, std::size_t len) override;
  void backup_memory_write(const void* src, std::size_t len) override;
  void backup_memory_clear(std::size_t len) override;

 private:
  template <class T>
  static bool take(std::optional<T>& pending, T* out) {
    if (!pending) return false;
    *out = *pending;
    pending.reset();
    return true;
  }
  std::string flash_;
  std::uint64_t now_us_ = 0;
  std::optional<rosflight_firmware::ImuStruct> imu_;
  std::optional<rosflight_firmware::MagStruct> mag_;
  std::optional<rosflight_firmware::PressureStruct> baro_, diff_;
  std::optional<rosflight_firmware::GnssStruct> gnss_;
  std::optional<rosflight_firmware::RcStruct> rc_;
  std::deque<std::uint8_t> rx_;
  std::vector<std::uint8_t> tx_;
  std::array<float, kOutputs> pwm_{}, pwm_rate_{};
  bool pwm_enabled_ = false, reboot_ = false, led0_ = false, led1_ = false;
  std::vector<std::uint8_t> backup_;
};

}  // namespace tern::fcu::sil
