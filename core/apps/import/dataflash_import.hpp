// core/apps/import/dataflash_import.hpp: `tern import dataflash`: an ArduPilot DataFlash log (.bin)
// into a sensor log (docs/sensor-log.md). import_dataflash itself is declared in importers.hpp; this
// header holds the conversions it is made of, so that tests can check them one by one.
//
// Messages (ArduPilot's names and labels, looked up by name in the log's own FMT messages, which
// change between ArduPilot versions; instance 0 only, where a message has an instance field `I`):
//   imu            IMU GyrX/Y/Z (rad/s), AccX/Y/Z (m/s^2), both body FRD (ArduPilot applied
//                  AHRS_ORIENTATION and the calibration); T (degC) as the temperature
//   gnss           GPS Status (AP_GPS::GPS_Status: 0-1 none, 2 2-D, 3-6 3-D), NSats, HDop, Lat/Lng
//                  (deg), Alt (m MSL), Spd (m/s) and GCrs (deg) as vel_n/vel_e, VZ (m/s, down); GPA
//                  (the same TimeUS and instance) HAcc, VAcc, SAcc, VDop, VV (0: the receiver gives
//                  no vertical velocity, then use_gnss_vel_d false); date from GWk/GMS (GPS time - 18 s)
//   baro           BARO Press (Pa), Temp (degC)
//   diff_pressure  ARSP DiffPress (Pa, ArduPilot's offset removed) scaled to the ideal pitot of the
//                  estimator: DiffPress * ARSPD_RATIO * 1.225 / 2, so that its EAS is ArduPilot's
//                  Airspeed (sqrt(DiffPress * ARSPD_RATIO)); Temp (degC)
//   mag            MAG MagX/Y/Z (mGauss, body frame, offsets removed) * 1e-7 = T
//   reference      ATT Roll/Pitch/Yaw (deg); POS Lat/Lng/Alt (deg, m MSL); XKF1 (else NKF1) VN/VE/VD;
//                  XKF2 (else NKF2) VWN/VWE; without ATT or POS, AHR2's (the backup DCM estimate)
//   actuators      RCOU C1..C14 (us) through the log's own PARM SERVOn_FUNCTION (4 aileron, 19
//                  elevator, 21 rudder, 70 throttle, 77/78 elevon left/right, 79/80 V-tail left/right)
//                  and SERVOn_MIN/TRIM/MAX/REVERSED, the surfaces' commands as the uavbook's deflections
//                  through --max-deflection (import/surface_commands.hpp)
//   excitation     SIDD Targ on a mixer axis (SIDS Ax 10-13: SYSID_AXIS Mixer Roll, Pitch, Yaw,
//                  Thrust: a fraction of the full command), 0 outside a manoeuvre
// Times: TimeUS (us since boot) minus the earliest TimeUS of the messages converted; stamp = that
// in ns. Rows are put in time order per output topic through a 1 s window, as for a ULog.
//
// The file is read twice, streaming both times: a survey (the parameters, the origin, which
// messages hold data), then the conversion.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "tern/msg/sensors.hpp"

namespace tern::core::dataflash_import {

/// AP_GPS::GPS_Status (0 no GPS, 1 no fix, 2 2-D, 3 3-D, 4 DGPS, 5 RTK float, 6 RTK fixed) as the
/// sensor log's fix type: 0-1 none, 2 2-D, 3-6 3-D, anything else none.
msg::FixType ardupilot_fix_type(int status);

/// The UTC date ("2024-05-01") of a GPS week and millisecond of the week (GPS time; UTC is 18 s
/// behind it since 2017); "" for week 0.
std::string iso_date_from_gps_week(std::int64_t week, std::int64_t week_ms);

/// One servo output's PARMs: SERVOn_MIN, _TRIM, _MAX (us), _REVERSED.
struct ServoRange {
  double min = 1100.0, trim = 1500.0, max = 1900.0;  ///< ArduPilot's defaults
  bool reversed = false;
};
/// A surface's pulse as ArduPilot's scaled output over its full range (-1..1: -4500..4500 centidegrees),
/// SRV_Channel's pwm_from_angle inverted: (pwm - trim) / (max - trim) above the trim, / (trim - min)
/// below, negated when reversed.
double angle_from_pwm(double pwm_us, const ServoRange& s);
/// A throttle pulse as 0..1 (SRV_Channel's pwm_from_range inverted): (pwm - min) / (max - min),
/// 1 minus that when reversed, clamped.
double range_from_pwm(double pwm_us, const ServoRange& s);

/// ArduPlane's elevon and V-tail mixer (servos.cpp, channel_function_mixer) inverted: out1 = (in2 -
/// in1) * gain, out2 = (in2 + in1) * gain, so in1 = (out2 - out1) / (2 gain), in2 = (out1 + out2) /
/// (2 gain). Elevons: in1 aileron, in2 elevator, out1 left, out2 right; V-tail: in1 rudder, in2
/// elevator, out1 right, out2 left.
struct Unmixed {
  double in1, in2;
};
Unmixed unmix(double out1, double out2, double gain);

}  // namespace tern::core::dataflash_import
