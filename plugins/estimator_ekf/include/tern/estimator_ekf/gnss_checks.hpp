// tern/estimator_ekf/gnss_checks.hpp: the GNSS start-up checks: whether a receiver has settled
// enough for its fixes to be used, the first of them as the estimator's origin (and the
// barometer's datum). How the estimator uses the verdicts: estimator.hpp, "Life of an estimate" 2.
//
// A receiver that has just acquired its first 3-D fix is not yet right: its altitude wanders by
// metres to tens of metres and its velocity shows metres per second while the aircraft sits
// still, for seconds to minutes as it collects ephemerides and its own filter converges. PX4 EKF2
// and ArduPilot EKF3 take nothing from it until a set of checks has passed for a continuous time.
// The method and the figures are PX4's (src/modules/ekf2/EKF/aid_sources/gnss/gnss_checks.cpp,
// runInitialFixChecks and runOnGroundGnssChecks; parameters in src/modules/ekf2/params_gnss.yaml),
// read as a specification; ArduPilot EKF3's calcGpsGoodToAlign (AP_NavEKF3_VehicleStatus.cpp,
// EK3_GPS_CHECK) runs the same kind of checks with looser thresholds (6 satellites, HDOP 2.5,
// hAcc 5 m, vAcc 7.5 m, sAcc 1 m/s, 3 m of decaying drift, 0.3 m/s filtered speeds, 10 s held).
//
// Per fix (update()), each check enabled in GnssCheckConfig::mask (PX4 EKF2_GPS_CHECK's bit
// positions) fails when:
//   bit 0 nsats   num_sats < min_sats                                  (EKF2_REQ_NSATS, 6)
//   bit 1 pdop    PDOP = sqrt(hdop^2 + vdop^2) > max_pdop              (EKF2_REQ_PDOP, 2.5; PX4's
//                 EKF2.cpp makes its pdop so from vehicle_gps_position); a receiver reporting
//                 HDOP alone (vdop 0): hdop > max_pdop, ArduPilot EKF3's geometry check
//                 (calcGpsGoodToAlign: hdopFail, "GPS HDOP %.1f (needs 2.5)")
//   bit 2 eph     h_acc > max_h_acc                                    (EKF2_REQ_EPH, 3 m)
//   bit 3 epv     v_acc > max_v_acc                                    (EKF2_REQ_EPV, 5 m)
//   bit 4 sacc    s_acc > max_s_acc                                    (EKF2_REQ_SACC, 0.5 m/s)
//   bit 5 hdrift  filtered horizontal position rate > max_h_drift       (EKF2_REQ_HDRIFT, 0.1 m/s)
//   bit 6 vdrift  filtered vertical position rate > max_v_drift         (EKF2_REQ_VDRIFT, 0.2 m/s)
//   bit 7 hspeed  filtered horizontal GNSS speed > max_h_drift          (EKF2_REQ_HDRIFT)
//   bit 8 vspeed  filtered vertical GNSS speed > max_v_drift            (EKF2_REQ_VDRIFT)
// and always when the fix is below the estimator's min_fix_type (bit kFixBit, not maskable). Bit 9
// (spoofing) selects nothing: msg::Gnss carries no spoofing flag, so a PX4 mask can be copied
// unchanged and that check is not run.
// The checks pass (passed(), latched) once no enabled check has failed for hold_time
// (EKF2_REQ_GPS_H, 10 s); the first fix counts as a failure, so a receiver good from its first fix
// passes hold_time after it. failing() == 0 before that: every check passes, not yet for long enough.
//
// Drift (bits 5-8): first-order low-pass filters with time constant drift_time_constant (PX4: 10 s)
// of the position change between fixes over their interval (the fix's own NED displacement,
// tern::GeoOrigin about the first fix) and of the reported velocity, each input clamped to
// +-10x its threshold (PX4's anti-windup), starting from zero. They run only while the aircraft
// is still on the ground (Motion::at_rest, the estimator's gyro-based rest test); on the ground
// but moving (carried, taxiing) the filters are reset and the last verdicts kept; in the air
// those checks pass and the filters are reset (PX4 runOnGroundGnssChecks). They need nothing the
// receiver reports beyond position and velocity, so they hold for a receiver without accuracies.
//
// Quantities a receiver does not report. msg::Gnss writes 0 for "not reported" (h_acc, v_acc,
// s_acc, hdop, vdop; num_sats). A log with dilutions but no accuracies (an ArduPilot GPS log's
// HDop; mavros' APPROXIMATED covariance) is judged on its geometry by the PDOP/HDOP check. PX4 tests `hacc > EKF2_REQ_EPH` and so passes a
// zero accuracy; ArduPilot EKF3 skips hAcc, vAcc and sAcc when the driver has none. tern does the same: an accuracy of 0 (or non-finite)
// passes its check. For the satellite count PX4 and ArduPilot fail a zero (nsats < 6); tern deviates and skips num_sats == 0 with a fix at
// or above min_fix_type, since a 3-D fix from no satellite is impossible and the 0 can only mean the log has no count (the Zurich 2014 and
// ALFA logs: with PX4's rule they would never pass). A receiver reporting nothing then rests on the drift checks alone while still on the
// ground, and in the air on the fix type and the hold time alone: what such a log can say.
//
// What PX4 does after the start-up checks (runSimplifiedChecks: loose accuracy limits in flight)
// is not here: the checks decide the origin, not the fusion of later fixes (the estimator's
// innovation gates do that).
//
// Plain C++: reads msg::Gnss, no host types; not thread safe.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "tern/geodesy.hpp"
#include "tern/msg/sensors.hpp"
#include "tern/param.hpp"
#include "tern/time.hpp"

namespace tern::ekf {

/// Bits of GnssCheckConfig::mask and GnssChecks::failing(): PX4 EKF2_GPS_CHECK's positions.
namespace gnss_check {
inline constexpr std::uint32_t nsats = 1u << 0;
inline constexpr std::uint32_t pdop = 1u << 1;
inline constexpr std::uint32_t eph = 1u << 2;
inline constexpr std::uint32_t epv = 1u << 3;
inline constexpr std::uint32_t sacc = 1u << 4;
inline constexpr std::uint32_t hdrift = 1u << 5;
inline constexpr std::uint32_t vdrift = 1u << 6;
inline constexpr std::uint32_t hspeed = 1u << 7;
inline constexpr std::uint32_t vspeed = 1u << 8;
/// tern's own: the fix is below min_fix_type (always checked).
inline constexpr std::uint32_t fix = 1u << 16;
}  // namespace gnss_check
/// The checks named by a set of gnss_check bits, e.g. "vertical drift, vertical speed" ("" for none).
std::string gnss_check_names(std::uint32_t bits);

/// The start-up checks' thresholds, with PX4 EKF2's parameter names and defaults.
struct GnssCheckConfig {
  std::int64_t mask = 1023;         ///< EKF2_GPS_CHECK (default 1023): bits as above; 0 leaves the fix type and the hold
  int min_sats = 6;                 ///< EKF2_REQ_NSATS, 6 (range 4-12)
  double max_pdop = 2.5;            ///< EKF2_REQ_PDOP, 2.5 (1.5-5); ArduPilot EKF3's HDOP limit, 2.5, where only HDOP is reported
  double max_h_acc = 3.0;           ///< m, EKF2_REQ_EPH, 3 m (2-100)
  double max_v_acc = 5.0;           ///< m, EKF2_REQ_EPV, 5 m (2-100)
  double max_s_acc = 0.5;           ///< m/s, EKF2_REQ_SACC, 0.5 m/s (0.5-5)
  double max_h_drift = 0.1;         ///< m/s, EKF2_REQ_HDRIFT, 0.1 m/s (0.1-1)
  double max_v_drift = 0.2;         ///< m/s, EKF2_REQ_VDRIFT, 0.2 m/s (0.1-1.5)
  double hold_time = 10.0;          ///< s, EKF2_REQ_GPS_H, 10 s: every enabled check passing this long
  double drift_time_constant = 10;  ///< s: the drift filters' (PX4 gnss_checks.cpp filt_time_const, 10 s; not a PX4 parameter)
  /// m/s: before the origin, a GNSS ground speed at least this says the aircraft flies (as a pitot
  /// airspeed at least min_airspeed does): ArduPilot EKF3 detectFlight's 5 m/s for a plane
  /// (without the arming state tern's estimator does not have). Motion::in_air for the drift checks.
  double in_air_ground_speed = 5.0;
  /// s: while waiting, a change of the failing checks is reported at most this often (the phase
  /// machine's preflight_report_interval, 5 s).
  double report_interval = 5.0;
  /// Once the start-up checks have passed, and before while flying, a fix is used only while its
  /// reported accuracies stay within these (PX4 gnss_checks.cpp runSimplifiedChecks: hacc > 50, vacc > 50, sacc > 10 fail):
  /// a receiver that says its solution is this poor is not fused, and cannot reset the estimate.
  double flight_max_h_acc = 50.0;  ///< m
  double flight_max_v_acc = 50.0;  ///< m
  double flight_max_s_acc = 10.0;  ///< m/s
  /// After the start-up checks: the fix's reported accuracies within the flight limits (0 or
  /// unreported: not checked).
  bool usable_in_flight(double h_acc, double v_acc, double s_acc) const {
    return !(h_acc > flight_max_h_acc) && !(v_acc > flight_max_v_acc) && !(s_acc > flight_max_s_acc);
  }

  template <class V>
  static void describe(V& v) {
    using tern::ParamSpec;
    using C = GnssCheckConfig;
    v(&C::mask, "gnss_check",
      ParamSpec("", 0, 1023,
                "GNSS start-up checks, PX4 EKF2_GPS_CHECK bits: 0 sats, 1 PDOP (HDOP alone where only it is reported), 2 h_acc, "
                "3 v_acc, 4 s_acc, 5 h drift, 6 v drift, 7 h speed, 8 v speed (9 spoofing: no such field, not run)"));
    v(&C::min_sats, "gnss_req_nsats", ParamSpec("", 4, 12, "satellites a fix needs (PX4 EKF2_REQ_NSATS; 0 reported: skipped)"));
    v(&C::max_pdop, "gnss_req_pdop",
      ParamSpec("", 1.5, 5.0, "largest reported PDOP, or HDOP where only it is reported (PX4 EKF2_REQ_PDOP; 0 reported: skipped)"));
    v(&C::max_h_acc, "gnss_req_eph", ParamSpec("m", 2.0, 100.0, "largest reported horizontal accuracy (PX4 EKF2_REQ_EPH)"));
    v(&C::max_v_acc, "gnss_req_epv", ParamSpec("m", 2.0, 100.0, "largest reported vertical accuracy (PX4 EKF2_REQ_EPV)"));
    v(&C::max_s_acc, "gnss_req_sacc", ParamSpec("m/s", 0.5, 5.0, "largest reported speed accuracy (PX4 EKF2_REQ_SACC)"));
    v(&C::max_h_drift, "gnss_req_hdrift",
      ParamSpec("m/s", 0.1, 1.0, "largest filtered horizontal drift and speed still on the ground (PX4 EKF2_REQ_HDRIFT)"));
    v(&C::max_v_drift, "gnss_req_vdrift",
      ParamSpec("m/s", 0.1, 1.5, "largest filtered vertical drift and speed still on the ground (PX4 EKF2_REQ_VDRIFT)"));
    v(&C::hold_time, "gnss_req_hold_time",
      ParamSpec("s", 0.0, 600.0,
                "the start-up checks must pass this long before the estimate is valid on the ground; the origin, the first passing fix, is "
                "provisional until then (PX4 EKF2_REQ_GPS_H)"));
    v(&C::drift_time_constant, "gnss_drift_time_constant", ParamSpec("s", 0.1, 100.0, "time constant of the drift filters"));
    v(&C::in_air_ground_speed, "gnss_check_in_air_speed",
      ParamSpec("m/s", 0.5, 100.0, "GNSS ground speed from which the start-up checks take the aircraft as flying (drift checks off)"));
    v(&C::flight_max_h_acc, "gnss_flight_max_eph",
      ParamSpec("m", 1.0, 1000.0, "after the start-up checks, fixes reporting a larger horizontal accuracy are not used (PX4: 50 m)"));
    v(&C::flight_max_v_acc, "gnss_flight_max_epv",
      ParamSpec("m", 1.0, 1000.0, "after the start-up checks, fixes reporting a larger vertical accuracy are not used (PX4: 50 m)"));
    v(&C::flight_max_s_acc, "gnss_flight_max_sacc",
      ParamSpec("m/s", 0.1, 100.0, "after the start-up checks, fixes reporting a larger speed accuracy are not used (PX4: 10 m/s)"));
    v(&C::report_interval, "gnss_check_report_interval",
      ParamSpec("s", 0.0, 600.0, "while waiting for the GNSS checks, changes of the failing checks are reported at most this often"));
  }
};

class GnssChecks {
 public:
  /// What the aircraft does, as the caller knows it: still on the ground (the drift checks run),
  /// on the ground but moving (they pause), or flying (they pass).
  enum class Motion : std::uint8_t { at_rest, moving, in_air };

  explicit GnssChecks(const GnssCheckConfig& config = {}) : c_(config) {}
  void set_config(const GnssCheckConfig& config) { c_ = config; }

  /// One fix (any fix type; `usable`: at or above the estimator's min_fix_type). Returns passed().
  bool update(const msg::Gnss& fix, bool usable, Motion motion);
  /// The checks have passed once (latched; later fixes change nothing).
  bool passed() const { return passed_; }
  /// The enabled checks the last fix failed (gnss_check bits; 0 once passed).
  std::uint32_t failing() const { return failing_; }
  /// Stamp of the first fix seen and of the fix that passed (-1: none yet).
  Nanos first_stamp() const { return first_stamp_; }
  Nanos passed_stamp() const { return passed_stamp_; }
  /// The filtered drifts of the last fix still on the ground (m/s; kept while moving on the
  /// ground, 0 in the air): horizontal and vertical position rate, horizontal and vertical speed.
  double h_drift() const { return h_drift_; }
  double v_drift() const { return v_drift_; }
  double h_speed() const { return h_speed_; }
  double v_speed() const { return v_speed_; }
  /// The fix fails an enabled quality check of the start-up set (satellites, DOP, reported
  /// accuracies; not the drifts): the receiver itself says its solution is degraded. Usable for
  /// every fix, before and after passed().
  bool degraded(const msg::Gnss& fix) const { return (fix_failures(fix, true) & c_.mask) != 0; }
  /// The failing checks with their values and limits, e.g. "vertical drift 0.83 m/s > 0.2".
  std::string describe_failing() const;

 private:
  std::uint32_t fix_failures(const msg::Gnss& f, bool usable) const;
  std::uint32_t flight_failures(const msg::Gnss& f, bool usable) const;  ///< the in-flight limits only
  void run_drift(const msg::Gnss& f, Motion motion);
  void reset_drift();

  GnssCheckConfig c_;
  bool passed_ = false;
  std::uint32_t failing_ = 0;
  std::uint32_t drift_failing_ = 0;  ///< the drift checks' verdicts, kept while moving on the ground
  msg::Gnss last_{};                 ///< the last fix (failing values for describe_failing)
  Nanos first_stamp_ = -1, passed_stamp_ = -1, last_fail_ = -1;
  std::optional<tern::GeoOrigin> frame_;  ///< NED frame about the first usable fix: displacements
  Eigen::Vector3d prev_ned_ = Eigen::Vector3d::Zero();
  Nanos prev_stamp_ = -1;                                ///< previous usable fix (-1: none, or the drift filters were reset)
  Eigen::Vector3d rate_filt_ = Eigen::Vector3d::Zero();  ///< low-passed NED position rate, m/s
  Eigen::Vector3d vel_filt_ = Eigen::Vector3d::Zero();   ///< low-passed NED velocity (n, e clamped per axis), m/s
  double h_drift_ = 0.0, v_drift_ = 0.0, h_speed_ = 0.0, v_speed_ = 0.0;
};

}  // namespace tern::ekf
