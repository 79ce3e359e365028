// sil/sil_bench.cpp: --bench-calibration: the IMU calibration ROSflight asks for before flying
// ("level and still"), done as a user does it on the bench, before the aircraft goes to the field:
// the firmware boots from the board's flash, gets ROSFLIGHT_CMD_ACCEL_CALIBRATION over its serial
// port (what `tern fcu calibrate imu` and rosflight_io's calibrate_imu send), runs its own
// calibration (sensors.cpp calibrate_accel and calibrate_gyro: 1000 samples), says "IMU offsets
// captured", and ROSFLIGHT_CMD_WRITE_PARAMS saves the offsets to flash. The same sensor unit
// (seed) as in the flight, held level and still (no wind, no vibration).
//
// It runs in a child process: the firmware keeps state in function-local statics
// (comm_manager.cpp) that a second boot in the same process would inherit; the flight's firmware
// then boots in this process from the flash the child wrote, as after a power cycle.
#include <iostream>
#include <optional>

#include <sys/wait.h>
#include <unistd.h>

#include "tern/math.hpp"
#include "../emulator/util.hpp"
#include "mavlink_adapter.hpp"
#include "rosflight.h"
#include "sil.hpp"
#include "tern_fcu_serial/fcu_side.hpp"

namespace tern::fcu::sil {

namespace {
constexpr std::int64_t kBenchLimit = 30'000'000'000;  // ns: the calibrations take about 2.5 s each
}  // namespace

/// The aircraft on the bench: level, still, in still air.
sim::Truth Sil::bench_truth() const {
  sim::Truth t;
  t.x = sim::make_state(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0, 0, 0);
  t.mass = ac_.mass;
  t.rho = ac_.rho;
  t.fm.f_gravity = Eigen::Vector3d(0, 0, ac_.mass * tern::kGravity);  // held still: no net force (the world's g, sim_aero model.cpp)
  return t;
}

void Sil::bench_calibration() {
  std::cout.flush();
  std::cerr.flush();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("--bench-calibration: fork failed");
  if (pid == 0) _exit(run_bench());
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("--bench-calibration: the firmware did not store its IMU calibration (see the line above)");
}

/// The child's session; its exit code: 0 when the offsets are in flash.
int Sil::run_bench() {
  boot();
  mavlink::Encoder enc(1, 50);  // the companion's ids (rosflight_io's)
  mavlink::Parser parser;
  std::vector<std::uint8_t> to_fcu;
  auto command = [&](RosflightCmd c) {
    mavlink::RosflightCmd m;
    m.command = static_cast<std::uint8_t>(c);
    to_fcu.clear();
    enc.append(m, to_fcu);
    board_.receive_bytes(to_fcu.data(), to_fcu.size());
  };
  mavlink::Heartbeat hb;  // the companion is there: the firmware sends its log lines only then (comm_manager.cpp)
  enc.append(hb, to_fcu);
  board_.receive_bytes(to_fcu.data(), to_fcu.size());
  command(RosflightCmd::accel_calibration);
  const sim::Truth truth = bench_truth();
  std::optional<int> result;
  for (std::int64_t t = 0; t < kBenchLimit && !result; t += dt_) {
    board_.set_time_us(static_cast<std::uint64_t>(board_us(t)));
    const auto m = sensors_.imu(truth, static_cast<double>(dt_) * 1e-9);
    rosflight_firmware::ImuStruct s{};
    s.header.timestamp = static_cast<std::uint64_t>(board_us(t));
    for (int i = 0; i < 3; ++i) {
      s.accel[i] = static_cast<float>(m.accel[i]);
      s.gyro[i] = static_cast<float>(m.gyro[i]);
    }
    s.temperature = static_cast<float>(m.temperature);
    board_.put_imu(s);
    fw_->run();
    const std::vector<std::uint8_t> sent = board_.take_sent();
    parser.feed(sent.data(), sent.size(), [&](const mavlink::Frame& f) {
      const auto msg = mavlink::decode(f);
      if (const auto* text = msg ? std::get_if<mavlink::Statustext>(&*msg) : nullptr) {
        const std::string line = mavlink::to_string(text->text);
        if (line == "IMU offsets captured") {
          std::cerr << "tern-fcu-sil: bench: " << line << "\n";
          command(RosflightCmd::write_params);
        } else if (text->severity <= 3 && line.rfind("Unable to arm", 0) != 0) {
          std::cerr << "tern-fcu-sil: bench: " << line << "\n";
          result = 1;
        }
      } else if (const auto* ack = msg ? std::get_if<mavlink::RosflightCmdAck>(&*msg) : nullptr) {
        if (ack->command == static_cast<std::uint8_t>(RosflightCmd::write_params))
          result = ack->success == 1 ? 0 : 1;  // ROSFLIGHT_CMD_SUCCESS
      }
    });
  }
  if (!result) std::cerr << "tern-fcu-sil: bench: no IMU calibration within " << kBenchLimit / 1'000'000'000 << " s\n";
  fw_.reset();
  adapter_.reset();
  return result.value_or(1);
}

}  // namespace tern::fcu::sil
