// plugin_messages.cpp: what the FCU's messages other than SMALL_IMU mean for tern: sensor
// messages into tern's types, RC read as rosflight_io reads it, the status in words (one line
// per change), STATUSTEXT by severity. See fcu_serial_plugin.hpp.
#include <spdlog/spdlog.h>

#include "fcu_serial_plugin.hpp"
#include "tern_fcu_serial/status.hpp"

namespace tern::fcu_serial {

void FcuSerial::handle_other(const mav::Message& m, const fcu::Received& r, fcu::FlightTime stream, Due& due) {
  if (const auto* s = std::get_if<mav::SmallMag>(&m)) {
    msg::Mag out;
    out.stamp = stream.ns;
    out.field = Eigen::Vector3d(s->xmag, s->ymag, s->zmag) * mag_scale_();
    due.mag = out;
  } else if (const auto* s = std::get_if<mav::SmallBaro>(&m)) {
    msg::Baro out;
    out.stamp = stream.ns;
    out.pressure = s->pressure;
    out.temperature = s->temperature;
    due.baro = out;
  } else if (const auto* s = std::get_if<mav::DiffPressure>(&m)) {
    msg::DiffPressure out;
    out.stamp = stream.ns;
    out.pressure = s->diff_pressure;
    out.temperature = s->temperature;
    due.diff = out;
  } else if (const auto* s = std::get_if<mav::RosflightGnss>(&m)) {
    due.gnss = gnss(*s, r, stream);
  } else if (const auto* s = std::get_if<mav::RcChannels>(&m)) {
    s_.rc_seen = true;
    due.rc = rc(*s, stream);
  } else if (const auto* s = std::get_if<mav::RosflightStatus>(&m)) {
    on_status(*s, stream);
    due.status = true;
  } else if (const auto* s = std::get_if<mav::Timesync>(&m)) {
    clock_.timesync().on_answer(*s, r.rx_ns);
  } else if (const auto* s = std::get_if<mav::Statustext>(&m)) {
    log_text(*s);
  } else if (const auto* s = std::get_if<mav::RosflightVersion>(&m)) {
    s_.version = mav::to_string(s->version);
    log().info("FCU firmware {}", s_.version);
  } else if (const auto* s = std::get_if<mav::RosflightCmdAck>(&m)) {
    if (!s->success) log().warn("FCU refused command {}", static_cast<int>(s->command));
  } else if (const auto* s = std::get_if<mav::RosflightOutputRaw>(&m)) {
    s_.output_raw = *s;  // stamp: the FCU's clock_millis (CommManager::send_output_raw)
  }
}

/// rosflight_timestamp is the FCU's time the fix was read from the receiver (firmware
/// src/mavlink_adapter.cpp, MavlinkAdapter::send_gnss, packs GnssStruct::header.timestamp,
/// "time of data read complete" in include/interface/board.h): the best time of validity the
/// link offers; the receiver's own solution-to-output latency is not reported.
msg::Gnss FcuSerial::gnss(const mav::RosflightGnss& s, const fcu::Received& r, fcu::FlightTime stream) const {
  msg::Gnss out;
  out.stamp = clock_.timed(fcu::FcuTime{static_cast<std::int64_t>(s.rosflight_timestamp) * 1000}, fcu::HostTime{r.rx_ns}, stream).ns;
  out.fix_type = static_cast<msg::FixType>(fcu::fix_type(s.fix_type));
  out.num_sats = s.num_sat;
  out.lat = s.lat;
  out.lon = s.lon;
  out.alt = s.height;
  out.vel = Eigen::Vector3d(s.vel_n, s.vel_e, s.vel_d);
  out.h_acc = s.h_acc;
  out.v_acc = s.v_acc;
  out.s_acc = s.s_acc;
  out.time_of_validity = out.stamp;
  return out;
}

msg::Rc FcuSerial::rc(const mav::RcChannels& s, fcu::FlightTime stream) const {
  const fcu::RcSticks k = fcu::from_rc(s, rc_map_);
  msg::Rc out;
  out.stamp = stream.ns;
  out.roll = k.roll;
  out.pitch = k.pitch;
  out.yaw = k.yaw;
  out.throttle = k.throttle;
  out.aux = k.aux;
  out.rc_override = s_.status && s_.status->rc_override;
  out.failsafe = s_.status && s_.status->failsafe;
  return out;
}

/// ROSFLIGHT_STATUS: published; every change of arming, errors, failsafe or override is one
/// log line saying what it means and what is missing.
void FcuSerial::on_status(const mav::RosflightStatus& s, fcu::FlightTime stream) {
  msg::FcuStatus st = s_.status.value_or(msg::FcuStatus{});
  const std::optional<mav::RosflightStatus> was = s_.raw_status;
  st.stamp = stream.ns;
  st.armed = s.armed != 0;
  st.failsafe = s.failsafe != 0;
  st.rc_override = (s.rc_override & fcu::kPilotOverride) != 0;  // the pilot flies (not: tern's command missing)
  st.offboard = s.offboard != 0;
  st.error_code = s.error_code;
  const double t = tern::to_seconds(stream.ns);
  if (!was || was->armed != s.armed || was->error_code != s.error_code) {
    const std::string why = fcu::arming_problems(st.armed, s.error_code);
    if (why.empty())
      log().info("t={:.3f} s: FCU armed, no errors", t);
    else
      log().warn("t={:.3f} s: {}", t, why);
  }
  if (!was || was->failsafe != s.failsafe) {
    if (st.failsafe)
      log().warn("t={:.3f} s: FCU failsafe ON (RC lost: throttle 0, surfaces neutral)", t);
    else if (was)
      log().warn("t={:.3f} s: FCU failsafe off", t);
  }
  if (!was || was->rc_override != s.rc_override) {
    const std::string why = fcu::describe_override(s.rc_override);
    if (!why.empty())
      log().warn("t={:.3f} s: RC override 0x{:03x}: {}", t, s.rc_override, why);
    else if (was)
      log().info("t={:.3f} s: RC override off: tern flies", t);
  }
  s_.raw_status = s;
  s_.status = st;
}

/// STATUSTEXT by MAV_SEVERITY: 0-3 error, 4 warning, else info.
void FcuSerial::log_text(const mav::Statustext& s) {
  const std::string text = mav::to_string(s.text);
  if (s.severity <= 3)
    log().error("FCU: {}", text);
  else if (s.severity <= 4)
    log().warn("FCU: {}", text);
  else
    log().info("FCU: {}", text);
}

}  // namespace tern::fcu_serial
