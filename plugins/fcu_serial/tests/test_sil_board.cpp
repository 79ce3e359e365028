// tern's SIL board (tools/sil/sil_board.hpp) alone, against the firmware's Board interface:
// what each read hands the firmware, the serial queues, PWM, flash and backup memory.
#include <doctest/doctest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "sil_board.hpp"

using tern::fcu::sil::SilBoard;
namespace rf = rosflight_firmware;

namespace {
std::string temp_file(const char* name) { return (std::filesystem::temp_directory_path() / name).string(); }
}  // namespace

TEST_CASE("a sample is read once: the next read has nothing new, as a driver's data-ready flag") {
  SilBoard b("");
  rf::ImuStruct in{}, out{};
  CHECK_FALSE(b.imu_read(&out));
  in.header.timestamp = 1'002'500;
  in.accel[2] = -9.81f;
  b.put_imu(in);
  REQUIRE(b.imu_read(&out));
  CHECK(out.header.timestamp == 1'002'500);
  CHECK(out.accel[2] == -9.81f);
  CHECK_FALSE(b.imu_read(&out));
  rf::RangeStruct r{};
  rf::BatteryStruct bat{};
  CHECK_FALSE(b.range_read(&r));  // no range finder, no battery monitor in sim_aero
  CHECK_FALSE(b.battery_read(&bat));
}

TEST_CASE("the clock is the loop's: micros and millis of the time set") {
  SilBoard b("");
  b.set_time_us(12'345'678);
  CHECK(b.clock_micros() == 12'345'678u);
  CHECK(b.clock_millis() == 12'345u);
}

TEST_CASE("serial: bytes in arrive in order; what the firmware writes is taken once") {
  SilBoard b("");
  const std::uint8_t in[] = {0xFE, 1, 2, 3};
  b.receive_bytes(in, sizeof in);
  CHECK(b.serial_bytes_available() == 4);
  CHECK(b.serial_read() == 0xFE);
  CHECK(b.serial_read() == 1);
  CHECK(b.serial_bytes_available() == 2);
  const std::uint8_t out[] = {9, 8};
  b.serial_write(out, 2, 0);
  b.serial_write(out, 1, 1);
  CHECK(b.take_sent() == std::vector<std::uint8_t>{9, 8, 9});
  CHECK(b.take_sent().empty());
}

TEST_CASE("PWM: nothing before pwm_init; rates kept; pwm_disable zeroes the outputs") {
  SilBoard b("");
  std::array<float, SilBoard::kOutputs> v{};
  v[0] = 0.75f;
  b.pwm_write(v.data(), SilBoard::kOutputs);
  CHECK(b.pwm()[0] == 0.0f);
  const float rates[10] = {50, 50, 50, 50, 490, 50, 50, 50, 50, 50};
  b.pwm_init(rates, 10);
  CHECK(b.pwm_rate()[4] == 490.0f);
  CHECK(b.pwm_rate()[12] == 0.0f);
  b.pwm_write(v.data(), SilBoard::kOutputs);
  CHECK(b.pwm()[0] == 0.75f);
  b.pwm_disable();
  CHECK(b.pwm()[0] == 0.0f);
  CHECK_FALSE(b.pwm_enabled());
}

TEST_CASE("flash: a block written is read back; a missing file or another size reads nothing") {
  const std::string f = temp_file("tern_sil_board_test.flash");
  std::filesystem::remove(f);
  SilBoard b(f);
  std::array<std::uint8_t, 64> block{}, back{};
  CHECK_FALSE(b.memory_read(back.data(), back.size()));
  for (std::size_t i = 0; i < block.size(); ++i) block[i] = static_cast<std::uint8_t>(i * 7);
  REQUIRE(b.memory_write(block.data(), block.size()));
  CHECK(std::filesystem::file_size(f) == block.size());
  SilBoard again(f);  // a power cycle
  REQUIRE(again.memory_read(back.data(), back.size()));
  CHECK(back == block);
  std::array<std::uint8_t, 65> other{};
  CHECK_FALSE(again.memory_read(other.data(), other.size()));  // another firmware's block size
  std::filesystem::remove(f);
  SilBoard none("");
  CHECK_FALSE(none.memory_write(block.data(), block.size()));
}

TEST_CASE("flash in a directory that cannot be written: write fails, the old block stays") {
  SilBoard b("/proc/tern-no-such-dir/flash");
  const std::uint8_t x = 1;
  CHECK_FALSE(b.memory_write(&x, 1));
}

TEST_CASE("backup memory survives in RAM; a read of another size or after clear finds nothing") {
  SilBoard b("");
  const std::uint32_t data = 0xDEADBEEF;
  std::uint32_t back = 0;
  CHECK_FALSE(b.backup_memory_read(&back, sizeof back));
  b.backup_memory_write(&data, sizeof data);
  REQUIRE(b.backup_memory_read(&back, sizeof back));
  CHECK(back == data);
  b.backup_memory_clear(sizeof data);
  CHECK_FALSE(b.backup_memory_read(&back, sizeof back));
}

TEST_CASE("board_reset asks the loop for a reboot") {
  SilBoard b("");
  CHECK_FALSE(b.reboot_requested());
  b.board_reset(false);
  CHECK(b.reboot_requested());
  b.clear_reboot();
  CHECK_FALSE(b.reboot_requested());
}
