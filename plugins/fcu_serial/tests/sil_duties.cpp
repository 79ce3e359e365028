// tern-fcu-sil's own duties, checked over the link like a companion sees them: its --params
// upload reaches the firmware's flash, a bad entry is one line and exit code 1 (both programs
// share that contract), --bench-calibration leaves the firmware calibrated, and
// --companion-silence makes the firmware hand the channels to RC after OFFBOARD_TIMEOUT.
#include <doctest/doctest.h>

#include "fcu_process.hpp"
#include "tern_fcu_serial/status.hpp"

using namespace tern::fcu;
using namespace tern::fcu::testing;
namespace mav = tern::fcu::mavlink;

namespace {
constexpr const char* kArm = "0 throttle=0 aux1=-1 aux2=-1; 2 aux2=1; 2.1 aux1=1; 2.5 aux2=-1";  // armed at FCU 3.1 s

std::size_t lines(const std::string& s) {
  std::size_t n = 0;
  for (char c : s) n += c == '\n';
  return n;
}
}  // namespace

TEST_CASE("tern-fcu-sil --params: the values reach the firmware (PARAM_REQUEST_READ), its mixer is valid") {
  const TempFile params("sil-params.yaml", "FIXED_WING: 1\nPRIMARY_MIXER: 9\nRC_F_AXIS: 0\nRC_OVRD_DEV: 0.25\nRC_OVRD_LAG_T: 500\n");
  Setup s;
  s.configured = false;
  s.rc = "none";
  s.args = {"--params", params.path()};
  FcuProcess f(Program::firmware, s);
  CHECK(f.param_get("FIXED_WING") == 1.0);
  CHECK(f.param_get("PRIMARY_MIXER") == 9.0);
  CHECK(f.param_get("RC_F_AXIS") == 0.0);
  CHECK(f.param_get("RC_OVRD_DEV") == doctest::Approx(0.25f));
  CHECK(f.param_get("RC_OVRD_LAG_T") == 500.0);
  CHECK(f.param_get("RC_NUM_CHN") == 6.0);  // not in the file: the firmware's default
  f.run_for(0.2);
  const auto st = f.last<mav::RosflightStatus>();
  REQUIRE(st);
  CHECK((st->error_code & firmware::kErrorInvalidMixer) == 0);
  CHECK(f.said("Invalid mixer choice for primary mixer") == std::nullopt);
}

TEST_CASE("--params with a bad entry: one line naming file, parameter and value; exit code 1 (both programs)") {
  const TempFile unknown("unknown.yaml", "PRIMARY_MIXER: 9\nNO_SUCH_PARAM: 1\n");
  const TempFile not_int("not-int.yaml", "RC_NUM_CHN: 1.5\n");
  const TempFile not_float("not-float.yaml", "RC_OVRD_DEV: fast\n");
  for (const Program p : {Program::emulator, Program::firmware}) {
    CAPTURE(to_string(p));
    const std::string name = p == Program::emulator ? "tern-fcu-emulator: " : "tern-fcu-sil: ";
    struct Case {
      const TempFile& file;
      std::string says;
    };
    for (const Case& c : {Case{unknown, "NO_SUCH_PARAM is not a parameter"}, Case{not_int, "RC_NUM_CHN: '1.5' is not an int32"},
                          Case{not_float, "RC_OVRD_DEV: 'fast' is not a finite number"}}) {
      const Outcome o = run_to_end(p, {"--params", c.file.path(), "--lockstep"});
      CAPTURE(o.output);
      CHECK(o.exit_code == 1);
      CHECK(lines(o.output) == 1);
      CHECK(o.output.rfind(name + "--params " + c.file.path() + ": ", 0) == 0);
      CHECK(o.output.find(c.says) != std::string::npos);
    }
  }
}

TEST_CASE("tern-fcu-sil --bench-calibration: accelerometer and gyro biases stored, no 'IMU not calibrated', arms by RC") {
  Setup s;  // the Anaconda's flash (no calibration in it) and --bench-calibration
  s.rc = kArm;
  FcuProcess f(Program::firmware, s);
  for (const char* n : {"ACC_X_BIAS", "ACC_Y_BIAS", "ACC_Z_BIAS", "GYRO_X_BIAS", "GYRO_Y_BIAS", "GYRO_Z_BIAS"}) {
    CAPTURE(n);
    const auto v = f.param_get(n);
    REQUIRE(v);
    CHECK(*v != 0.0);
  }
  REQUIRE(f.run_until([&] { return f.last<mav::RosflightStatus>() && f.last<mav::RosflightStatus>()->armed; }, 5.0));
  CHECK(f.first_status([](const mav::RosflightStatus& st) { return (st.error_code & firmware::kErrorUncalibratedImu) != 0; }) ==
        std::nullopt);
  CHECK(f.said("Unable to arm: IMU not calibrated") == std::nullopt);

  Setup raw;  // the same flash without the bench: the firmware refuses to arm
  raw.configured = false;
  raw.rc = kArm;
  raw.args = {"--params", TERN_FCU_CONFIGS "/anaconda_rosflight_sil.yaml"};
  FcuProcess g(Program::firmware, raw);
  g.run_for(3.5);
  REQUIRE(g.last<mav::RosflightStatus>());
  CHECK((g.last<mav::RosflightStatus>()->error_code & firmware::kErrorUncalibratedImu) != 0);
  CHECK(g.last<mav::RosflightStatus>()->armed == 0);
  CHECK(g.said("Unable to arm: IMU not calibrated"));
}

TEST_CASE("tern-fcu-sil --companion-silence: after OFFBOARD_TIMEOUT the firmware hands every channel to RC, then back") {
  Setup s;
  s.rc = kArm;
  s.firmware_args = {"--companion-silence", "4:5"};  // FCU 5..6 s
  FcuProcess f(Program::firmware, s);
  REQUIRE(f.run_until([&] { return f.last<mav::RosflightStatus>() && f.last<mav::RosflightStatus>()->armed; }, 5.0));
  f.set_surfaces({0.2, 0, 0, 0.5});
  f.run_until([&] { return f.now() >= 6.5; }, 4.0);
  const auto before = f.all<mav::RosflightStatus>(4.5);
  REQUIRE_FALSE(before.empty());
  CHECK(before.front().second.rc_override == 0);
  const auto handed =
      f.first_status([](const mav::RosflightStatus& st) { return (st.rc_override & kOffboardInactive) == kOffboardInactive; }, 5.0);
  REQUIRE(handed);
  // the first RC frame more than OFFBOARD_TIMEOUT (100 ms) after the last command that reached it (4.9975 s)
  CHECK(*handed == doctest::Approx(5.1));
  for (const auto& [t, o] : f.all<mav::RosflightOutputRaw>(5.2))
    if (t < 5.95) {
      CHECK(o.values[0] == doctest::Approx(0.5));  // the pilot's centred stick
      CHECK(o.values[4] == 0.0f);                  // the pilot's throttle stick at 0
    }
  const auto back = f.first_status([](const mav::RosflightStatus& st) { return st.rc_override == 0; }, *handed + 1e-3);
  REQUIRE(back);
  CHECK(*back >= 6.0);
  CHECK(*back < 6.05);
  CHECK(f.last<mav::RosflightOutputRaw>()->values[0] == doctest::Approx(0.6));
  CHECK(f.last<mav::RosflightOutputRaw>()->values[4] == doctest::Approx(0.5));
}
