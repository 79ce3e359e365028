// bench_fcu_serial: MAVLink parser throughput (MB/s) on a ROSflight-like stream, with and without
// corruption, and the time to encode one frame (ns). Prints a table and writes
// bench/results/bench_fcu_serial.json. Not a test: numbers depend on the machine.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "tern_fcu_serial/codec.hpp"

using namespace tern::fcu::mavlink;
using Clock = std::chrono::steady_clock;

namespace {
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// One second of ROSflight's stream (400 Hz IMU, 100 Hz baro and pitot, 50 Hz mag, RC and
/// attitude, 10 Hz GNSS and status), repeated `seconds` times.
std::vector<std::uint8_t> stream(int seconds) {
  Encoder enc(1, 1);
  std::vector<std::uint8_t> out;
  for (int s = 0; s < seconds; ++s)
    for (int k = 0; k < 400; ++k) {
      SmallImu imu;
      imu.time_boot_us = static_cast<std::uint64_t>(s) * 1000000 + static_cast<std::uint64_t>(k) * 2500;
      imu.zacc = -9.81f;
      enc.append(imu, out);
      if (k % 4 == 0) {
        enc.append(SmallBaro{}, out);
        enc.append(DiffPressure{}, out);
      }
      if (k % 8 == 0) {
        enc.append(SmallMag{}, out);
        enc.append(RcChannels{}, out);
        enc.append(AttitudeQuaternion{}, out);
      }
      if (k % 40 == 0) {
        enc.append(RosflightGnss{}, out);
        enc.append(RosflightStatus{}, out);
      }
    }
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double parse_mbps(const std::vector<std::uint8_t>& data, std::size_t& frames) {
  std::vector<double> rates;
  for (int rep = 0; rep < 7; ++rep) {
    Parser p;
    std::size_t n = 0;
    const auto t0 = Clock::now();
    p.feed(data.data(), data.size(), [&](const Frame& f) { n += f.len; });
    const double dt = seconds_since(t0);
    frames = static_cast<std::size_t>(p.stats().frames);
    rates.push_back(static_cast<double>(data.size()) / dt / 1e6);
    if (n == 0) std::printf("(no frames)\n");
  }
  return median(rates);
}

template <class T>
double encode_ns(const T& msg) {
  std::vector<double> v;
  std::uint8_t out[kMaxFrameLength];
  for (int rep = 0; rep < 7; ++rep) {
    const int N = 1'000'000;
    unsigned sink = 0;
    const auto t0 = Clock::now();
    for (int i = 0; i < N; ++i) {
      sink += static_cast<unsigned>(encode(msg, static_cast<std::uint8_t>(i), 1, 1, out));
      sink += out[7];
    }
    const double dt = seconds_since(t0);
    if (sink == 0) std::printf("(sink)\n");
    v.push_back(dt / N * 1e9);
  }
  return median(v);
}
}  // namespace

int main() {
  const auto clean = stream(300);  // 5 minutes of flight
  auto dirty = clean;
  std::mt19937_64 rng(1);
  for (std::size_t i = 0; i < dirty.size(); i += 997) dirty[i] ^= static_cast<std::uint8_t>(1 + rng() % 255);
  std::size_t frames_clean = 0, frames_dirty = 0;
  const double mb_clean = parse_mbps(clean, frames_clean);
  const double mb_dirty = parse_mbps(dirty, frames_dirty);
  SmallImu imu;
  imu.time_boot_us = 123;
  OffboardControl oc;
  oc.u = {0.1f, 0.2f, 0.3f, 0.4f};
  const double ns_imu = encode_ns(imu);
  const double ns_oc = encode_ns(oc);
  const double link_mbps = 921600.0 / 10.0 / 1e6;  // 921600 baud, 10 bits per byte

  std::printf("bench_fcu_serial (median of 7)\n");
  std::printf("%-42s %12s\n", "measure", "value");
  std::printf("%-42s %9.1f MB/s (%zu frames, %.1f MB)\n", "parse, clean ROSflight stream", mb_clean, frames_clean, clean.size() / 1e6);
  std::printf("%-42s %9.1f MB/s (%zu frames)\n", "parse, 1 byte in 997 corrupted", mb_dirty, frames_dirty);
  std::printf("%-42s %9.1f x\n", "parse rate / 921600-baud link rate", mb_clean / link_mbps);
  std::printf("%-42s %9.1f ns\n", "encode SMALL_IMU frame", ns_imu);
  std::printf("%-42s %9.1f ns\n", "encode OFFBOARD_CONTROL frame", ns_oc);

  const std::filesystem::path dir = TERN_BENCH_RESULTS_DIR;
  std::filesystem::create_directories(dir);
  std::ofstream j(dir / "bench_fcu_serial.json");
  j << "{\n"
    << "  \"parse_clean_MBps\": " << mb_clean << ",\n"
    << "  \"parse_corrupted_MBps\": " << mb_dirty << ",\n"
    << "  \"frames_clean\": " << frames_clean << ",\n"
    << "  \"frames_corrupted\": " << frames_dirty << ",\n"
    << "  \"parse_over_link_rate\": " << mb_clean / link_mbps << ",\n"
    << "  \"encode_small_imu_ns\": " << ns_imu << ",\n"
    << "  \"encode_offboard_control_ns\": " << ns_oc << "\n"
    << "}\n";
  return 0;
}
