// fcu_process.hpp: one of the two FCU programs (tern-fcu-emulator, tern's re-implementation of
// the ROSflight firmware, or tern-fcu-sil, the real firmware on tern's SIL board) run in
// lockstep over its pseudo-terminal, with a companion of the tests' own in front of it: what the
// behaviour tests (sil_behaviours.cpp, sil_duties.cpp) see is only what comes over the link.
//
// The companion answers every SMALL_IMU it receives with exactly one OFFBOARD_CONTROL (the
// current command) and, once per simulated second, a HEARTBEAT before it (the firmware sends its
// STATUSTEXT lines only after a HEARTBEAT: comm_manager.cpp log_message). Frames the test sends
// (PARAM_SET, ROSFLIGHT_CMD, ...) go out with the next answer. Every frame received is kept
// with the FCU time of the SMALL_IMU it follows (its own stamp for SMALL_IMU), in seconds of the
// FCU's clock (both programs read 1 s at their first sample).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tern_fcu_serial/codec.hpp"
#include "tern_fcu_serial/fcu_side.hpp"
#include "tern_fcu_serial/mapping.hpp"
#include "tern_fcu_serial/process.hpp"

namespace tern::fcu::testing {

enum class Program { emulator, firmware };
const char* to_string(Program p);  ///< "emulator", "real firmware"

/// The world and stored parameters the FCU starts with.
struct Setup {
  /// true: the Anaconda's FCU as shipped (fixed-wing mixer, AETR + arm/override switches) with
  /// its IMU calibrated: the emulator's configs/fcu/anaconda_rosflight.yaml (gyro biases stored),
  /// the firmware's anaconda_rosflight_sil.yaml with --bench-calibration. false: no --params
  /// (the firmware's defaults: invalid mixer, uncalibrated IMU).
  bool configured = true;
  std::string rc = "0 throttle=0 aux1=-1 aux2=-1; 2 aux2=1; 2.1 aux1=1; 2.5 aux2=-1";  ///< --rc, world seconds (FCU time - 1 s)
  std::vector<std::string> args;           ///< further options of both programs (--wind, --silence ...)
  std::vector<std::string> firmware_args;  ///< further options of tern-fcu-sil only
};

/// One frame from the FCU.
struct Received {
  double t = 0;  ///< FCU time, s
  mavlink::Frame frame;
  mavlink::Message msg;
};

class FcuProcess {
 public:
  /// Starts the program with --lockstep on a pseudo-terminal and opens it; throws
  /// std::runtime_error (with the program's stderr) if it does not announce its port.
  FcuProcess(Program program, const Setup& setup);
  ~FcuProcess();
  FcuProcess(const FcuProcess&) = delete;
  FcuProcess& operator=(const FcuProcess&) = delete;

  Program program() const { return program_; }
  /// The OFFBOARD_CONTROL answered to every IMU sample from now on (default: pass-through, all
  /// of u[0..9] active at 0).
  void set_command(const mavlink::OffboardControl& c) { command_ = c; }
  /// Pass-through of surfaces as tern's plugin sends them (mapping.hpp to_offboard), with a
  /// maximum deflection of 1 rad: delta_a etc. are the commands u in -1..1.
  void set_surfaces(const Surfaces& s);
  /// Sends m once, with the next answer.
  template <class T>
  void send(const T& m) {
    companion_.append(m, pending_);
  }

  /// Runs the lockstep until pred() holds (checked after each batch of frames) or max_s
  /// simulated seconds have passed; returns whether pred() held. Throws std::runtime_error if
  /// the program stops sending for 10 s of wall time or ends.
  bool run_until(const std::function<bool()>& pred, double max_s);
  void run_for(double s);
  double now() const { return now_; }  ///< FCU time of the newest SMALL_IMU, s

  const std::vector<Received>& log() const { return log_; }
  /// Every message of type T received at or after FCU time `from`, with its time.
  template <class T>
  std::vector<std::pair<double, T>> all(double from = 0) const {
    std::vector<std::pair<double, T>> out;
    for (const Received& r : log_)
      if (r.t >= from)
        if (const T* m = std::get_if<T>(&r.msg)) out.emplace_back(r.t, *m);
    return out;
  }
  template <class T>
  std::optional<T> last() const {
    for (auto it = log_.rbegin(); it != log_.rend(); ++it)
      if (const T* m = std::get_if<T>(&it->msg)) return *m;
    return std::nullopt;
  }
  /// FCU time of the first STATUSTEXT saying `text` (at or after `from`), or nullopt.
  std::optional<double> said(std::string_view text, double from = 0) const;
  /// FCU time of the first ROSFLIGHT_STATUS at or after `from` for which pred holds.
  std::optional<double> first_status(const std::function<bool(const mavlink::RosflightStatus&)>& pred, double from = 0) const;

  /// PARAM_REQUEST_READ by name; the value (int32 parameters bit for bit), or nullopt within max_s.
  std::optional<double> param_get(const std::string& name, double max_s = 0.5);
  /// PARAM_SET of `type` (kParamInt32 / kParamReal32) to system `target`.
  void param_set(const std::string& name, double value, std::uint8_t type, std::uint8_t target = 1);
  /// ROSFLIGHT_CMD; its ROSFLIGHT_CMD_ACK within max_s, or nullopt.
  std::optional<mavlink::RosflightCmdAck> command(RosflightCmd c, double max_s = 0.5);

  const mavlink::ParserStats& stats() const { return parser_.stats(); }
  /// What the program wrote to stderr so far.
  std::string errors() const;
  /// SIGTERM; its exit status.
  int stop();

 private:
  void answer(double t);
  void on_frame(const mavlink::Frame& f);
  bool pump(std::int64_t wall_timeout_ns);

  Program program_;
  std::string stderr_file_;
  std::unique_ptr<ChildProcess> child_;
  int fd_ = -1;
  mavlink::Parser parser_;
  mavlink::Encoder companion_{1, 50};  // rosflight_io's ids
  mavlink::OffboardControl command_;
  std::vector<std::uint8_t> pending_;
  std::vector<Received> log_;
  double now_ = 0, next_heartbeat_ = 0;
};

/// Runs a program to its end with the given arguments (after --aircraft); its exit code and
/// everything it wrote to stdout and stderr.
struct Outcome {
  int exit_code = -1;
  std::string output;
};
Outcome run_to_end(Program program, const std::vector<std::string>& args);

/// Path of a temporary file holding `text` (removed by the destructor).
class TempFile {
 public:
  TempFile(const std::string& stem, const std::string& text);
  ~TempFile();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace tern::fcu::testing
