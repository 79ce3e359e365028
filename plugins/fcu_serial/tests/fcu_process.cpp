// fcu_process.cpp: see fcu_process.hpp.
#include "fcu_process.hpp"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

namespace tern::fcu::testing {

namespace {
constexpr std::int64_t kSilentLimitNs = 10'000'000'000;  // wall time without a byte: the program hangs
constexpr std::int64_t kStartLimitNs = 60'000'000'000;   // wall time to the port line (bench calibration included)
const std::string kAircraft = TERN_AIRCRAFT_DIR "/anaconda.yaml";

const char* path(Program p) { return p == Program::emulator ? TERN_FCU_EMULATOR : TERN_FCU_SIL; }

/// A word for sh -c, single-quoted.
std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string command_line(Program p, const std::vector<std::string>& args) {
  std::string cmd = "exec " + quote(path(p)) + " --aircraft " + quote(kAircraft);
  for (const auto& a : args) cmd += " " + quote(a);
  return cmd;
}

std::string temp_path(const std::string& stem) {
  static std::atomic<int> n{0};
  return (std::filesystem::temp_directory_path() / ("tern-" + std::to_string(getpid()) + "-" + std::to_string(n++) + "-" + stem)).string();
}

std::string read_file(const std::string& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The program's arguments: lockstep on a pseudo-terminal, the stored parameters, the pilot.
std::vector<std::string> arguments(Program p, const Setup& s) {
  std::vector<std::string> a{"--lockstep", "--exit-with-parent", "--rc", s.rc};
  if (s.configured && p == Program::emulator) a.insert(a.end(), {"--params", TERN_FCU_CONFIGS "/anaconda_rosflight.yaml"});
  if (s.configured && p == Program::firmware)
    a.insert(a.end(), {"--params", TERN_FCU_CONFIGS "/anaconda_rosflight_sil.yaml", "--bench-calibration"});
  a.insert(a.end(), s.args.begin(), s.args.end());
  if (p == Program::firmware) a.insert(a.end(), s.firmware_args.begin(), s.firmware_args.end());
  return a;
}

int open_raw(const std::string& pty) {
  const int fd = ::open(pty.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) throw std::runtime_error("cannot open " + pty + ": " + std::strerror(errno));
  termios t{};
  tcgetattr(fd, &t);
  cfmakeraw(&t);
  tcsetattr(fd, TCSANOW, &t);
  return fd;
}

void write_all(int fd, const std::vector<std::uint8_t>& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t w = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (w > 0) {
      done += static_cast<std::size_t>(w);
    } else if (w < 0 && (errno == EAGAIN || errno == EINTR)) {
      pollfd p{fd, POLLOUT, 0};
      poll(&p, 1, 100);
    } else {
      throw std::runtime_error(std::string("cannot write to the FCU: ") + std::strerror(errno));
    }
  }
}
}  // namespace

const char* to_string(Program p) { return p == Program::emulator ? "emulator" : "real firmware"; }

FcuProcess::FcuProcess(Program program, const Setup& setup) : program_(program), stderr_file_(temp_path("fcu-stderr")) {
  for (std::size_t i = 0; i < 10; ++i) command_.u[i] = 0.0f;  // pass-through, everything active at 0
  const std::string cmd = command_line(program, arguments(program, setup)) + " 2>" + quote(stderr_file_);
  child_ = std::make_unique<ChildProcess>(std::vector<std::string>{"/bin/sh", "-c", cmd});
  std::string line;
  try {
    line = child_->read_line(kStartLimitNs);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string(to_string(program)) + ": " + e.what() + "; stderr: " + errors());
  }
  if (line.rfind("pty: ", 0) != 0) throw std::runtime_error(std::string(to_string(program)) + " said '" + line + "', not its port");
  fd_ = open_raw(line.substr(5));
}

FcuProcess::~FcuProcess() {
  stop();
  std::error_code ec;
  std::filesystem::remove(stderr_file_, ec);
}

int FcuProcess::stop() {
  const int status = child_ ? child_->stop() : -1;
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  return status;
}

std::string FcuProcess::errors() const { return read_file(stderr_file_); }

void FcuProcess::set_surfaces(const Surfaces& s) {
  ActuatorMap map;
  map.max_deflection = {1.0, 1.0, 1.0};
  command_ = to_offboard(s, map);
}

/// The companion's answer to one IMU sample: a HEARTBEAT once per simulated second, what the
/// test queued, one OFFBOARD_CONTROL.
void FcuProcess::answer(double t) {
  std::vector<std::uint8_t> out;
  if (t >= next_heartbeat_) {
    companion_.append(mavlink::Heartbeat{}, out);
    next_heartbeat_ = t + 1.0;
  }
  out.insert(out.end(), pending_.begin(), pending_.end());
  pending_.clear();
  companion_.append(command_, out);
  write_all(fd_, out);
}

void FcuProcess::on_frame(const mavlink::Frame& f) {
  const auto m = mavlink::decode(f);
  if (!m) return;
  if (const auto* imu = std::get_if<mavlink::SmallImu>(&*m)) now_ = static_cast<double>(imu->time_boot_us) * 1e-6;
  log_.push_back({now_, f, *m});
  if (std::holds_alternative<mavlink::SmallImu>(*m)) answer(now_);
}

/// Reads what the FCU sent (waiting at most wall_timeout_ns); false if nothing came.
bool FcuProcess::pump(std::int64_t wall_timeout_ns) {
  pollfd p{fd_, POLLIN, 0};
  const int r = poll(&p, 1, static_cast<int>(wall_timeout_ns / 1'000'000));
  if (r <= 0) return false;
  std::uint8_t buf[8192];
  const ssize_t n = ::read(fd_, buf, sizeof buf);
  if (n <= 0) {
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) return true;
    throw std::runtime_error(std::string(to_string(program_)) + " closed its port; stderr: " + errors());
  }
  parser_.feed(buf, static_cast<std::size_t>(n), [&](const mavlink::Frame& f) { on_frame(f); });
  return true;
}

bool FcuProcess::run_until(const std::function<bool()>& pred, double max_s) {
  if (fd_ < 0) throw std::logic_error("run_until: the FCU was stopped");
  while (now_ == 0.0)
    if (!pump(kSilentLimitNs)) throw std::runtime_error(std::string(to_string(program_)) + ": no frame within 10 s; stderr: " + errors());
  const double end = now_ + max_s;
  for (;;) {
    if (pred()) return true;
    if (now_ >= end) return false;
    if (!pump(kSilentLimitNs))
      throw std::runtime_error(std::string(to_string(program_)) + ": silent for 10 s at FCU time " + std::to_string(now_) +
                               "; stderr: " + errors());
  }
}

void FcuProcess::run_for(double s) {
  run_until([] { return false; }, s);
}

std::optional<double> FcuProcess::said(std::string_view text, double from) const {
  for (const auto& [t, m] : all<mavlink::Statustext>(from))
    if (mavlink::to_string(m.text) == text) return t;
  return std::nullopt;
}

std::optional<double> FcuProcess::first_status(const std::function<bool(const mavlink::RosflightStatus&)>& pred, double from) const {
  for (const auto& [t, s] : all<mavlink::RosflightStatus>(from))
    if (pred(s)) return t;
  return std::nullopt;
}

std::optional<double> FcuProcess::param_get(const std::string& name, double max_s) {
  mavlink::ParamRequestRead r;
  r.target_system = 1;
  r.param_id = mavlink::to_chars<16>(name);
  r.param_index = -1;
  send(r);
  const std::size_t mark = log_.size();
  std::optional<double> value;
  run_until(
      [&] {
        for (std::size_t i = mark; i < log_.size() && !value; ++i)
          if (const auto* v = std::get_if<mavlink::ParamValue>(&log_[i].msg); v && mavlink::to_string(v->param_id) == name)
            value = param_number(v->param_value, v->param_type);
        return value.has_value();
      },
      max_s);
  return value;
}

void FcuProcess::param_set(const std::string& name, double value, std::uint8_t type, std::uint8_t target) {
  mavlink::ParamSet s;
  s.target_system = target;
  s.param_id = mavlink::to_chars<16>(name);
  s.param_type = type;
  s.param_value = param_wire(value, type);
  send(s);
}

std::optional<mavlink::RosflightCmdAck> FcuProcess::command(RosflightCmd c, double max_s) {
  mavlink::RosflightCmd m;
  m.command = static_cast<std::uint8_t>(c);
  send(m);
  const std::size_t mark = log_.size();
  std::optional<mavlink::RosflightCmdAck> ack;
  run_until(
      [&] {
        for (std::size_t i = mark; i < log_.size() && !ack; ++i)
          if (const auto* a = std::get_if<mavlink::RosflightCmdAck>(&log_[i].msg); a && a->command == m.command) ack = *a;
        return ack.has_value();
      },
      max_s);
  return ack;
}

Outcome run_to_end(Program program, const std::vector<std::string>& args) {
  Outcome o;
  FILE* f = popen((command_line(program, args) + " 2>&1").c_str(), "r");
  if (f == nullptr) throw std::runtime_error(std::string("cannot start ") + path(program));
  char buf[512];
  while (std::fgets(buf, sizeof buf, f)) o.output += buf;
  const int status = pclose(f);
  o.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return o;
}

TempFile::TempFile(const std::string& stem, const std::string& text) : path_(temp_path(stem)) { std::ofstream(path_) << text; }

TempFile::~TempFile() {
  std::error_code ec;
  std::filesystem::remove(path_, ec);
}

}  // namespace tern::fcu::testing
