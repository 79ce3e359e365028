// fcu_serial_plugin.hpp: the tern plugin that flies through a ROSflight flight-control unit (FCU)
// over its MAVLink link (serial port or UDP), or through tern-fcu-emulator. See README.md.
//
// Ports (all optional to the host; outputs are published when the FCU sends the message):
//   in  actuators      Actuators: delta_a/e/r rad (uavbook signs), delta_t 0..1 -> OFFBOARD_CONTROL
//                      (channels Qx Qy Qz Fx, mapping.hpp); none yet: every channel ignored (RC)
//   out imu            Imu: SMALL_IMU, specific force m/s^2 and rates rad/s in FRD body axes
//   out gnss           Gnss: ROSFLIGHT_GNSS, stamped at its rosflight_timestamp
//   out baro           Baro: SMALL_BARO, Pa and K
//   out diff_pressure  DiffPressure: DIFF_PRESSURE, Pa (after the FCU's boot calibration)
//   out mag            Mag: SMALL_MAG x mag_scale, T, body axes
//   out rc             Rc: RC_CHANNELS 1-8 as rosflight_io reads them (chancount ignored)
//   out fcu_status     FcuStatus: ROSFLIGHT_STATUS (armed, failsafe, pilot override, errors)
//
// Time: fcu_clock.hpp (FcuClock: FCU boot time, host steady clock, flight time). The clock
// policy `fcu` lets the FCU's IMU pace the flight: step(now) waits at most wait_timeout for
// the sample of `now` (the one bounded wait an io plugin may do, by design); `wall` maps FCU
// time with TIMESYNC and never waits. The host's base rate should equal the IMU rate (400 Hz).
//
// The body is split by job: plugin_params.cpp (parameters and mappings), plugin_link.cpp
// (link, emulator, what we send), plugin_step.cpp (step, waiting, stamping), plugin_messages.cpp
// (what the FCU's messages mean, status in words).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tern/plugin.hpp"
#include "tern_fcu_serial/codec.hpp"
#include "tern_fcu_serial/fcu_clock.hpp"
#include "tern_fcu_serial/link.hpp"
#include "tern_fcu_serial/mapping.hpp"
#include "tern_fcu_serial/process.hpp"

namespace tern::fcu_serial {

namespace msg = tern::msg;
namespace fcu = tern::fcu;
namespace mav = tern::fcu::mavlink;

class FcuSerial final : public tern::Plugin {
 public:
  ~FcuSerial() override;
  void configure() override;
  void start() override;
  void reset() override;
  void stop() override;
  void step(tern::Nanos now) override;
  std::vector<std::pair<std::string, double>> summary() const override;
  /// The link's frame count (heartbeats and TIMESYNC go at wall-clock rates) and round trip.
  std::vector<std::pair<std::string, double>> timing() const override;
  /// The link's trouble, when it had any: losses, reboots, CRC errors, skipped bytes.
  std::string health() const override;

  // ---- for tests ----
  std::uint64_t link_losses() const { return s_.link_losses; }
  std::uint64_t reboots() const { return s_.reboots; }
  std::uint64_t commands_sent() const { return s_.commands_sent; }
  const fcu::TimeSync& timesync() const { return clock_.timesync(); }
  const fcu::ActuatorMap& actuator_mapping() const { return map_; }
  const std::optional<mav::RosflightOutputRaw>& last_output_raw() const { return s_.output_raw; }
  const std::string& fcu_version() const { return s_.version; }
  fcu::LinkStats link_stats() const { return link_ ? link_->stats() : final_stats_; }

 private:
  /// The messages of one step's kind that are due (a port holds one message per step).
  struct Due {
    std::optional<msg::Imu> imu;
    std::optional<msg::Mag> mag;
    std::optional<msg::Baro> baro;
    std::optional<msg::DiffPressure> diff;
    std::optional<msg::Gnss> gnss;
    std::optional<msg::Rc> rc;
    bool status = false;
  };
  /// Everything that lives one connection (start() to stop()): replaced whole by start().
  struct Session {
    std::deque<fcu::Received> pending;
    bool link_lost = false, imu_stalled = false, owed_command = false, rc_seen = false, rc_warned = false;
    std::optional<fcu::FcuTime> newest_imu;
    std::int64_t last_cmd_index = -1;
    fcu::HostTime last_rx, lost_at, last_heartbeat, last_timesync;
    tern::Nanos last_step_now = 0;
    std::optional<tern::Nanos> first_step_now;
    std::uint64_t link_losses = 0, reboots = 0, commands_sent = 0, imu_superseded = 0, lockstep_resends = 0;
    std::optional<msg::FcuStatus> status;
    std::optional<mav::RosflightStatus> raw_status;
    std::optional<mav::RosflightOutputRaw> output_raw;
    std::string version;
  };

  // plugin_params.cpp
  void declare_ports();
  void declare_link_params();
  /// The settings derived from start-only parameters (clock policy, actuator and RC maps):
  /// checked in configure(), taken up again by every start().
  void take_start_params();
  void declare_mapping_params();
  std::array<double, 3> default_max_deflection() const;
  std::array<double, 3> aircraft_max_deflection() const;
  std::string qname(const std::string& p) const;
  fcu::ActuatorMap actuator_map(std::array<double, 3> max_deflection) const;
  fcu::RcMap rc_map() const;
  // plugin_link.cpp
  fcu::LinkOptions link_options() const;
  std::string find_emulator() const;
  void start_emulator();
  void start_calibration();
  int socket_pair(std::vector<std::string>& argv);
  void wait_first_imu(const fcu::LinkOptions& o);
  void shutdown();
  template <class T>
  void send(const T& m) {
    if (link_) link_->send(enc_->frame(m));
  }
  void send_heartbeat();
  void send_timesync();
  void send_command();
  void send_due(tern::Nanos now);
  void check_link(fcu::HostTime host);
  void log_link_summary();
  // plugin_step.cpp
  void pull();
  bool has_imu_pending() const;
  void wait_for(tern::Nanos now);
  bool lockstep_resend(tern::Nanos now);
  void follow_host(tern::Nanos now);
  void process(tern::Nanos now);
  bool take_imu(const mav::SmallImu& s, const fcu::Received& r, tern::Nanos now, Due& due);
  void publish(const Due& due);
  void warn_without_rc(tern::Nanos now);
  // plugin_messages.cpp
  void handle_other(const mav::Message& m, const fcu::Received& r, fcu::FlightTime stream, Due& due);
  msg::Gnss gnss(const mav::RosflightGnss& s, const fcu::Received& r, fcu::FlightTime stream) const;
  msg::Rc rc(const mav::RcChannels& s, fcu::FlightTime stream) const;
  void on_status(const mav::RosflightStatus& s, fcu::FlightTime stream);
  void log_text(const mav::Statustext& s);

  tern::Input<msg::Actuators> actuators_in_;
  tern::Output<msg::Imu> imu_out_;
  tern::Output<msg::Gnss> gnss_out_;
  tern::Output<msg::Baro> baro_out_;
  tern::Output<msg::DiffPressure> diff_out_;
  tern::Output<msg::Mag> mag_out_;
  tern::Output<msg::Rc> rc_out_;
  tern::Output<msg::FcuStatus> status_out_;

  tern::Param<std::string> transport_, device_, udp_host_, clock_name_, emulator_args_, emulator_path_, channels_, emulator_params_,
      emulator_rc_, emulator_firmware_, calibrate_, emulator_link_;
  tern::Param<std::int64_t> baud_, udp_bind_port_, udp_remote_port_, system_id_, component_id_;
  tern::Param<bool> lockstep_, emulator_;
  tern::Param<double> connect_timeout_, wait_timeout_, link_timeout_, command_rate_, heartbeat_rate_, timesync_rate_, mag_scale_;
  tern::Param<std::vector<double>> max_deflection_, signs_, rc_channels_, rc_aux_channels_, rc_signs_;

  fcu::ClockPolicy policy_ = fcu::ClockPolicy::fcu;  ///< `clock`, parsed in configure() and at every start()
  fcu::ActuatorMap map_;
  fcu::RcMap rc_map_;
  std::unique_ptr<fcu::ChildProcess> emulator_proc_;
  std::string emulator_device_;
  int emulator_socket_ = -1;  ///< our end of the emulator_link: socket pair (-1: none)
  std::unique_ptr<fcu::Link> link_;
  std::unique_ptr<mav::Encoder> enc_;
  fcu::LinkStats final_stats_;
  fcu::FcuClock clock_{fcu::ClockPolicy::fcu, 0};
  Session s_;
};

}  // namespace tern::fcu_serial
