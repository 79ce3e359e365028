// tern-fcu-emulator: plays a ROSflight flight-control unit over a pseudo-terminal (or UDP),
// with sim_aero's aircraft model, wind and sensor models behind it, so that tern flies through
// the real serial path (fcu_serial plugin, MAVLink codec, link thread, time mapping).
//
//   tern-fcu-emulator --aircraft configs/aircraft/anaconda.yaml [--lockstep] [--speed 1]
//
// prints "pty: /dev/pts/N" (or "udp: HOST:PORT") on stdout, then streams like ROSflight firmware:
// SMALL_IMU 400 Hz, SMALL_MAG 50 Hz, SMALL_BARO and DIFF_PRESSURE 100 Hz, ROSFLIGHT_GNSS 10 Hz,
// RC_CHANNELS 50 Hz, ATTITUDE_QUATERNION and ROSFLIGHT_OUTPUT_RAW 50 Hz, ROSFLIGHT_STATUS 10 Hz,
// HEARTBEAT 1 Hz; it answers parameter requests, ROSFLIGHT_CMD and TIMESYNC, and applies
// OFFBOARD_CONTROL pass-through commands to the aircraft (the FCU's RC fallback, centred sticks
// and no throttle, after 100 ms without a command). The ATTITUDE_QUATERNION it sends is the true
// attitude (a real FCU sends its own estimate).
//
// Pacing: free-running at --speed times real time (1: like a real FCU), or --lockstep: after
// each IMU sample it waits for one OFFBOARD_CONTROL before it integrates the next IMU period
// (the plugin's `lockstep: true`): flights then run as fast as the computer allows and do not
// depend on its load. Faults for tests: --silence T0:T1 (sends nothing), --reboot-at T (clock
// restarts at 0), --rc-override T0:T1 (the pilot's switch: RC flies), --corrupt P (each frame
// has one byte flipped with probability P).
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <sys/prctl.h>
#include <termios.h>
#include <unistd.h>

#include <utility>  // before Asio: Boost 1.74's awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>

#include "tern_fcu_serial/codec.hpp"
#include "tern_fcu_serial/fcu_side.hpp"
#include "tern_fcu_serial/mapping.hpp"
#include "tern_sim_aero/aircraft.hpp"
#include "tern_sim_aero/sensors.hpp"
#include "tern_sim_aero/simulator.hpp"
#include "tern_sim_aero/wind.hpp"

namespace {

namespace sim = tern::sim;
namespace fcu = tern::fcu;
namespace mav = tern::fcu::mavlink;

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop = true; }

std::int64_t mono_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
std::int64_t ns(double s) { return static_cast<std::int64_t>(std::llround(s * 1e9)); }

std::vector<double> numbers(const std::string& s, std::size_t n, const std::string& what) {
  std::vector<double> v;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, s.find(':') != std::string::npos ? ':' : ',');) {
    try {
      v.push_back(std::stod(item));
    } catch (const std::exception&) {
      throw std::runtime_error(what + ": '" + s + "' is not a list of numbers");
    }
  }
  if (v.size() != n) throw std::runtime_error(what + ": needs " + std::to_string(n) + " numbers, got '" + s + "'");
  return v;
}

/// The port: a pseudo-terminal's master side, or a UDP socket.
class Port {
 public:
  virtual ~Port() = default;
  virtual int fd() const = 0;
  virtual std::size_t read(std::uint8_t* buf, std::size_t n) = 0;  ///< 0 if nothing
  virtual bool write(const std::uint8_t* p, std::size_t n) = 0;   ///< false if dropped
};

class PtyPort final : public Port {
 public:
  PtyPort() {
    if (openpty(&master_, &slave_, name_, nullptr, nullptr) != 0)
      throw std::runtime_error(std::string("openpty failed: ") + std::strerror(errno));
    termios t{};
    tcgetattr(slave_, &t);
    cfmakeraw(&t);
    cfsetispeed(&t, B921600);
    cfsetospeed(&t, B921600);
    tcsetattr(slave_, TCSANOW, &t);
    fcntl(master_, F_SETFL, fcntl(master_, F_GETFL) | O_NONBLOCK);
  }
  ~PtyPort() override {
    close(master_);
    close(slave_);
  }
  const char* name() const { return name_; }
  int fd() const override { return master_; }
  std::size_t read(std::uint8_t* buf, std::size_t n) override {
    const ssize_t r = ::read(master_, buf, n);
    return r > 0 ? static_cast<std::size_t>(r) : 0;
  }
  bool write(const std::uint8_t* p, std::size_t n) override {
    while (n > 0) {
      const ssize_t w = ::write(master_, p, n);
      if (w < 0) {
        if (errno == EINTR) continue;
        if (errno == EAGAIN) {  // nobody reads: wait a little, as a UART would not, then drop
          pollfd pf{master_, POLLOUT, 0};
          if (poll(&pf, 1, 50) > 0) continue;
        }
        return false;
      }
      p += w;
      n -= static_cast<std::size_t>(w);
    }
    return true;
  }

 private:
  int master_ = -1, slave_ = -1;
  char name_[256] = {};
};

class UdpPort final : public Port {
 public:
  UdpPort(const std::string& host, unsigned bind_port, unsigned remote_port) : sock_(io_) {
    namespace asio = boost::asio;
    const auto addr = asio::ip::make_address(host);
    sock_.open(addr.is_v4() ? asio::ip::udp::v4() : asio::ip::udp::v6());
    sock_.set_option(asio::socket_base::reuse_address(true));
    sock_.bind({addr, static_cast<unsigned short>(bind_port)});
    sock_.non_blocking(true);
    remote_ = {addr, static_cast<unsigned short>(remote_port)};
  }
  int fd() const override { return const_cast<boost::asio::ip::udp::socket&>(sock_).native_handle(); }
  std::size_t read(std::uint8_t* buf, std::size_t n) override {
    boost::system::error_code ec;
    boost::asio::ip::udp::endpoint from;
    const std::size_t r = sock_.receive_from(boost::asio::buffer(buf, n), from, 0, ec);
    return ec ? 0 : r;
  }
  bool write(const std::uint8_t* p, std::size_t n) override {
    boost::system::error_code ec;
    sock_.send_to(boost::asio::buffer(p, n), remote_, 0, ec);
    return !ec;
  }

 private:
  boost::asio::io_context io_;
  boost::asio::ip::udp::socket sock_;
  boost::asio::ip::udp::endpoint remote_;
};

struct Options {
  std::string aircraft;
  std::uint64_t seed = 1;
  bool udp = false;
  std::string udp_host = "127.0.0.1";
  unsigned udp_port = 14525, udp_remote_port = 14520;
  bool lockstep = false;
  double speed = 1.0;
  double duration = 0;
  std::string wind = "0,0,0";
  std::string turbulence = "none";
  std::string init_mode = "ground";
  double init_altitude = 100, init_airspeed = 17, init_heading = 0;
  std::string max_deflection;  // empty: the aircraft's limits
  std::string channels = "0,1,2,3";
  std::string silence, rc_override;
  double reboot_at = -1;
  double corrupt = 0;
  double stall_timeout = 10;
  bool exit_with_parent = false;
};

class Emulator {
 public:
  Emulator(const Options& o, Port& port)
      : o_(o),
        port_(port),
        ac_(sim::load_aircraft(o.aircraft)),
        sim_(ac_, o.seed),
        sensors_(sim::SensorParams{}, o.seed ^ 0x9E3779B97F4A7C15ull),
        fcu_(fcu::FcuSide::default_params(), "tern-fcu-emulator 0.1 (ROSflight protocol)", 1, 1),
        rng_(o.seed ^ 0xC0FFEEull) {
    const auto ch = numbers(o.channels, 4, "--channels");
    for (int i = 0; i < 4; ++i) map_.channel[i] = static_cast<int>(ch[i]);
    if (o.max_deflection.empty()) {
      map_.max_deflection = {ac_.max_delta_a, ac_.max_delta_e, ac_.max_delta_r};
    } else {
      const auto m = numbers(o.max_deflection, 3, "--max-deflection");
      map_.max_deflection = {m[0], m[1], m[2]};
    }
    map_.validate();
    const auto w = numbers(o.wind, 3, "--wind");
    sim_.set_turbulence(sim::dryden_preset(o.turbulence));
    sim_.set_steady_wind(Eigen::Vector3d(w[0], w[1], w[2]));
    if (o.init_mode == "ground") {
      sim_.set_state(sim::rest_state(ac_, 0, 0, o.init_heading));
    } else if (o.init_mode == "air") {
      sim_.set_state(sim::make_state({0, 0, -o.init_altitude}, {o.init_airspeed, 0, 0}, 0, 0, o.init_heading));
    } else {
      throw std::runtime_error("--init-mode: '" + o.init_mode + "' is not ground or air");
    }
    if (!o.silence.empty()) {
      const auto s = numbers(o.silence, 2, "--silence");
      silence_ = {ns(s[0]), ns(s[1])};
    }
    if (!o.rc_override.empty()) {
      const auto s = numbers(o.rc_override, 2, "--rc-override");
      override_ = {ns(s[0]), ns(s[1])};
    }
    auto sched = [](double hz) {
      sim::SensorSchedule s;
      s.period = ns(1.0 / hz);
      return s;
    };
    imu_ = sched(400);
    mag_ = sched(50);
    baro_ = sched(100);
    diff_ = sched(100);
    gnss_ = sched(10);
    rc_ = sched(50);
    att_ = sched(50);
    raw_ = sched(50);
    status_ = sched(10);
    heartbeat_ = sched(1);
    dt_ = imu_.period;
  }

  int run() {
    const std::int64_t wall0 = mono_ns();
    const std::int64_t end = o_.duration > 0 ? ns(o_.duration) : INT64_MAX;
    std::uint64_t used = 0;
    bool warned_stall = false;
    while (!g_stop && t_ <= end) {
      if (o_.reboot_at >= 0 && !rebooted_ && t_ >= ns(o_.reboot_at)) {
        rebooted_ = true;
        boot_ = t_;
        mav::Statustext st;
        st.severity = 5;
        st.text = mav::to_chars<50>("rebooted");
        fcu_.encoder().append(st, out_);
        std::cerr << "tern-fcu-emulator: reboot at t = " << o_.reboot_at << " s\n";
      }
      publish_due(t_);
      flush();
      // Wait: for the companion's command (lockstep) or for the wall clock (free-running).
      if (o_.lockstep) {
        const std::int64_t stall_deadline = mono_ns() + ns(o_.stall_timeout);
        while (!g_stop && fcu_.commands() <= used) {
          const bool started = used > 0;
          const std::int64_t left = stall_deadline - mono_ns();
          if (started && left <= 0) {
            if (!warned_stall) std::cerr << "tern-fcu-emulator: no command for " << o_.stall_timeout << " s; running on\n";
            warned_stall = true;
            break;
          }
          service(started ? std::min<std::int64_t>(left, 100'000'000) : 100'000'000);
        }
        used = fcu_.commands();
      } else {
        const std::int64_t target = wall0 + static_cast<std::int64_t>(static_cast<double>(t_ + dt_) / o_.speed);
        for (std::int64_t left; !g_stop && (left = target - mono_ns()) > 0;) service(left);
        service(0);
      }
      if (g_stop) break;
      apply_command();
      sim_.step(static_cast<double>(dt_) * 1e-9);
      t_ += dt_;
    }
    std::cerr << "tern-fcu-emulator: stopped at t = " << static_cast<double>(t_) * 1e-9 << " s after " << fcu_.commands()
              << " commands (" << dropped_ << " frames not delivered)\n";
    return 0;
  }

 private:
  /// The FCU's clock (time since its boot): streaming starts 1 s after power-up, so it is never
  /// 0 (a TIMESYNC answer with tc1 = 0 would read as a request).
  std::int64_t fcu_time() const { return t_ - boot_ + 1'000'000'000; }
  bool silent(std::int64_t t) const { return silence_ && t >= silence_->first && t < silence_->second; }
  bool overridden(std::int64_t t) const { return override_ && t >= override_->first && t < override_->second; }

  /// Reads what the companion sent (waiting at most timeout_ns) and answers it.
  void service(std::int64_t timeout_ns) {
    pollfd p{port_.fd(), POLLIN, 0};
    const int r = poll(&p, 1, static_cast<int>(std::max<std::int64_t>(0, timeout_ns) / 1'000'000));
    if (r <= 0) return;
    std::uint8_t buf[4096];
    for (std::size_t n; (n = port_.read(buf, sizeof buf)) > 0;) {
      parser_.feed(buf, n, [&](const mav::Frame& f) {
        fcu_.handle(f, fcu_time(), out_);
        if (f.msgid == mav::OffboardControl::kId) last_cmd_t_ = t_;
      });
    }
    flush();
  }

  void flush() {
    if (out_.empty()) return;
    if (!silent(t_)) {
      if (!port_.write(out_.data(), out_.size())) ++dropped_;
    }
    out_.clear();
  }

  template <class T>
  void send(const T& m) {
    const std::size_t at = out_.size();
    fcu_.encoder().append(m, out_);
    if (o_.corrupt > 0 && std::uniform_real_distribution<double>(0, 1)(rng_) < o_.corrupt) {
      const std::size_t i = at + std::uniform_int_distribution<std::size_t>(0, out_.size() - at - 1)(rng_);
      out_[i] ^= static_cast<std::uint8_t>(1 + std::uniform_int_distribution<int>(0, 254)(rng_));
    }
  }

  void apply_command() {
    fcu::Surfaces s;  // RC fallback: centred sticks, no throttle
    const bool offboard = !overridden(t_) && last_cmd_t_ >= 0 && t_ - last_cmd_t_ <= 100'000'000;
    if (offboard) s = fcu::from_offboard(fcu_.command(), map_);
    offboard_ = offboard;
    sim_.set_command({s.delta_e, s.delta_a, s.delta_r, s.delta_t});
  }

  const sim::Truth& truth() {
    if (!truth_) {
      truth_.emplace();
      truth_->x = sim_.state();
      truth_->fm = sim_.evaluate();
      truth_->mass = ac_.mass;
      truth_->rho = ac_.rho;
    }
    return *truth_;
  }

  void publish_due(std::int64_t t) {
    using Poll = sim::SensorSchedule::Poll;
    truth_.reset();
    const std::int64_t ft = fcu_time();
    if (imu_.poll(t) == Poll::sample) {
      const auto m = sensors_.imu(truth(), imu_.dt_since_last(t));
      imu_.last_sample = t;
      mav::SmallImu s;
      s.time_boot_us = static_cast<std::uint64_t>(ft / 1000);
      s.xacc = static_cast<float>(m.accel.x());
      s.yacc = static_cast<float>(m.accel.y());
      s.zacc = static_cast<float>(m.accel.z());
      s.xgyro = static_cast<float>(m.gyro.x());
      s.ygyro = static_cast<float>(m.gyro.y());
      s.zgyro = static_cast<float>(m.gyro.z());
      s.temperature = static_cast<float>(m.temperature);
      send(s);
    }
    if (mag_.poll(t) == Poll::sample) {
      const auto m = sensors_.mag(truth(), mag_.dt_since_last(t));
      mag_.last_sample = t;
      mav::SmallMag s;
      s.xmag = static_cast<float>(m.field.x());
      s.ymag = static_cast<float>(m.field.y());
      s.zmag = static_cast<float>(m.field.z());
      send(s);
    }
    if (baro_.poll(t) == Poll::sample) {
      const auto m = sensors_.baro(truth(), baro_.dt_since_last(t));
      baro_.last_sample = t;
      mav::SmallBaro s;
      s.pressure = static_cast<float>(m.pressure);
      s.temperature = static_cast<float>(m.temperature);
      s.altitude = static_cast<float>(44330.77 * (1.0 - std::pow(m.pressure / 101325.0, 0.190263)));
      send(s);
    }
    if (diff_.poll(t) == Poll::sample) {
      const auto m = sensors_.diff_pressure(truth(), diff_.dt_since_last(t));
      diff_.last_sample = t;
      mav::DiffPressure s;
      s.diff_pressure = static_cast<float>(m.pressure);
      s.temperature = static_cast<float>(m.temperature);
      s.velocity = static_cast<float>(std::sqrt(2.0 * std::max(0.0, m.pressure) / ac_.rho));
      send(s);
    }
    if (gnss_.poll(t) == Poll::sample) {
      const auto m = sensors_.gnss(truth(), gnss_.dt_since_last(t));
      gnss_.last_sample = t;
      mav::RosflightGnss s;
      const std::int64_t unix_ns = 1'763'683'200'000'000'000 + t;  // a fixed epoch: repeatable
      s.seconds = unix_ns / 1'000'000'000;
      s.nanos = static_cast<std::int32_t>(unix_ns % 1'000'000'000);
      s.fix_type = m.fix ? 3 : 0;
      s.num_sat = static_cast<std::uint8_t>(m.num_sats);
      s.lat = m.lat;
      s.lon = m.lon;
      s.height = static_cast<float>(m.alt);
      s.vel_n = static_cast<float>(m.vel_ned.x());
      s.vel_e = static_cast<float>(m.vel_ned.y());
      s.vel_d = static_cast<float>(m.vel_ned.z());
      s.h_acc = static_cast<float>(m.h_acc);
      s.v_acc = static_cast<float>(m.v_acc);
      s.s_acc = static_cast<float>(m.s_acc);
      s.rosflight_timestamp = static_cast<std::uint64_t>(ft / 1000);
      send(s);
    }
    if (rc_.poll(t) == Poll::sample) {
      fcu::RcSticks k;
      k.aux[1] = overridden(t) ? 1.0 : -1.0;  // channel 5 (RC_ATT_OVRD_CHN): the override switch
      send(fcu::to_rc(k, fcu::RcMap{}, static_cast<std::uint32_t>(ft / 1'000'000)));
    }
    if (att_.poll(t) == Poll::sample) {
      const Eigen::Quaterniond q = sim::attitude(sim_.state());
      mav::AttitudeQuaternion a;
      a.time_boot_ms = static_cast<std::uint32_t>(ft / 1'000'000);
      a.q1 = static_cast<float>(q.w());
      a.q2 = static_cast<float>(q.x());
      a.q3 = static_cast<float>(q.y());
      a.q4 = static_cast<float>(q.z());
      a.rollspeed = static_cast<float>(sim_.state()[sim::P]);
      a.pitchspeed = static_cast<float>(sim_.state()[sim::Q]);
      a.yawspeed = static_cast<float>(sim_.state()[sim::R]);
      send(a);
    }
    if (raw_.poll(t) == Poll::sample) {
      const sim::Deltas& d = sim_.surfaces();
      mav::RosflightOutputRaw r;
      r.stamp = static_cast<std::uint64_t>(ft / 1000);
      r.values[0] = static_cast<float>(d.delta_a / map_.max_deflection[0]);
      r.values[1] = static_cast<float>(d.delta_e / map_.max_deflection[1]);
      r.values[2] = static_cast<float>(d.delta_r / map_.max_deflection[2]);
      r.values[3] = static_cast<float>(d.delta_t);
      send(r);
    }
    if (status_.poll(t) == Poll::sample) {
      mav::RosflightStatus s;
      s.armed = 1;
      s.failsafe = 0;
      s.rc_override = overridden(t) ? 0x0F : 0;  // attitude and throttle overridden
      s.offboard = offboard_ ? 1 : 0;
      s.control_mode = 0;
      s.loop_time_us = 250;
      send(s);
    }
    if (heartbeat_.poll(t) == Poll::sample) {
      mav::Heartbeat h;
      h.type = 1;        // MAV_TYPE_FIXED_WING
      h.autopilot = 12;  // MAV_AUTOPILOT_GENERIC... (ROSflight reports its own value; unused by tern)
      h.base_mode = 0x80;
      h.system_status = 4;
      h.mavlink_version = 3;
      send(h);
    }
  }

  Options o_;
  Port& port_;
  sim::Aircraft ac_;
  sim::Simulator sim_;
  sim::Sensors sensors_;
  fcu::FcuSide fcu_;
  fcu::ActuatorMap map_;
  mav::Parser parser_;
  std::mt19937_64 rng_;
  std::vector<std::uint8_t> out_;
  std::optional<sim::Truth> truth_;
  sim::SensorSchedule imu_, mag_, baro_, diff_, gnss_, rc_, att_, raw_, status_, heartbeat_;
  std::optional<std::pair<std::int64_t, std::int64_t>> silence_, override_;
  std::int64_t t_ = 0, dt_ = 2'500'000, boot_ = 0, last_cmd_t_ = -1;
  bool rebooted_ = false, offboard_ = false;
  std::uint64_t dropped_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tern-fcu-emulator: a ROSflight FCU on a pseudo-terminal (or UDP), flying sim_aero's aircraft"};
  Options o;
  app.add_option("--aircraft", o.aircraft, "aircraft file (tern or ROSflight format)")->required()->check(CLI::ExistingFile);
  app.add_option("--seed", o.seed, "random seed of turbulence and sensor noise");
  app.add_flag("--udp", o.udp, "UDP instead of a pseudo-terminal (ROSflight SIL ports)");
  app.add_option("--udp-host", o.udp_host, "UDP address");
  app.add_option("--udp-port", o.udp_port, "our UDP port (ROSflight SIL: 14525)");
  app.add_option("--udp-remote-port", o.udp_remote_port, "the companion's UDP port (rosflight_io: 14520)");
  app.add_flag("--lockstep", o.lockstep, "wait for one OFFBOARD_CONTROL per IMU sample");
  app.add_option("--speed", o.speed, "free-running: simulated seconds per wall second")->check(CLI::Range(0.01, 1000.0));
  app.add_option("--duration", o.duration, "stop after this many simulated seconds (0: run until stopped)");
  app.add_option("--wind", o.wind, "steady wind n,e,d (m/s, NED)");
  app.add_option("--turbulence", o.turbulence, "Dryden turbulence")->check(CLI::IsMember({"none", "light", "moderate"}));
  app.add_option("--init-mode", o.init_mode, "ground (at rest) or air (level)")->check(CLI::IsMember({"ground", "air"}));
  app.add_option("--init-altitude", o.init_altitude, "m (air)");
  app.add_option("--init-airspeed", o.init_airspeed, "m/s (air)");
  app.add_option("--init-heading", o.init_heading, "rad");
  app.add_option("--max-deflection", o.max_deflection, "a,e,r rad at full pass-through command (default: the aircraft's limits)");
  app.add_option("--channels", o.channels, "pass-through channels of aileron, elevator, rudder, throttle");
  app.add_option("--silence", o.silence, "T0:T1 s: send nothing in this window (link loss)");
  app.add_option("--reboot-at", o.reboot_at, "s: the FCU reboots (its clock restarts at 0)");
  app.add_option("--rc-override", o.rc_override, "T0:T1 s: the pilot's override switch is on (RC flies)");
  app.add_option("--corrupt", o.corrupt, "probability that a frame gets one byte flipped")->check(CLI::Range(0.0, 1.0));
  app.add_option("--stall-timeout", o.stall_timeout, "lockstep: run on after this many wall seconds without a command");
  app.add_flag("--exit-with-parent", o.exit_with_parent, "stop when the process that started it ends (the plugin passes it)");
  CLI11_PARSE(app, argc, argv);

  std::signal(SIGTERM, on_signal);
  std::signal(SIGINT, on_signal);
  std::signal(SIGPIPE, SIG_IGN);
  if (o.exit_with_parent) {
    const pid_t parent = getppid();
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) return 0;  // the parent ended before prctl took effect
  }
  try {
    std::unique_ptr<Port> port;
    std::string where;
    if (o.udp) {
      port = std::make_unique<UdpPort>(o.udp_host, o.udp_port, o.udp_remote_port);
      where = "udp: " + o.udp_host + ":" + std::to_string(o.udp_port);
    } else {
      auto pty = std::make_unique<PtyPort>();
      where = std::string("pty: ") + pty->name();
      port = std::move(pty);
    }
    Emulator emu(o, *port);  // loads the aircraft first: a bad file fails before the port is announced
    std::cout << where << std::endl;
    return emu.run();
  } catch (const std::exception& e) {
    std::cerr << "tern-fcu-emulator: " << e.what() << "\n";
    return 1;
  }
}
