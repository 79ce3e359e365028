#!/usr/bin/python3
"""dataflash_log.py LOG OUT.bin [--aircraft FILE] [--date YYYY-MM-DD] [--check BIN_DIR]: a sensor log (tern's
docs/sensor-log.md: topics/*.csv and sensor_log.yaml, e.g. a flight rewritten by foreign_log.py) written as an
ArduPilot DataFlash log (issue 76: identification on the flights users bring, through the format they bring).

The format, from its specification (ArduPilot's libraries/AP_Logger/LogStructure.h and the sensors'
LogStructure.h files): every message is 0xA3 0x95, a type byte and the packed little-endian fields of that
type; FMT (type 128, 89 bytes) defines each type's length, four-letter name, format characters and labels;
c C e E are stored as the value * 100 and L as degrees * 1e7. The messages and labels are ArduPlane 4.5's
(ARDUPLANE_45; tests/fuzz/make_dataflash_seeds.py writes its seeds with the same encoder and layouts), in
the units ArduPilot logs and `tern import dataflash` converts back (core/apps/import/dataflash_import.hpp):

  sensor log                      DataFlash
  imu  accel (m/s^2), gyro        IMU AccX/Y/Z, GyrX/Y/Z: the same units, body FRD (ArduPilot's body frame); T degC
       (rad/s), temperature (K)
  gnss lat, lon (deg), alt (m),   GPS Lat/Lng (deg * 1e7), Alt (cm), Spd = |(vel_n, vel_e)| (m/s), GCrs its course
       vel_n/e/d (m/s), fix_type,   from north (deg, 0..360), VZ = vel_d (m/s, down); Status 3 for a 3-D fix, 2 for
       num_sats, hdop, vdop,        2-D, 1 otherwise; NSats; HDop (* 100); GWk/GMS from the date; GPA (same
       h_acc, v_acc, s_acc          TimeUS) VDop (* 100), HAcc, VAcc (cm), SAcc (cm/s), VV 1
                                    time_of_validity is not in the format: stamp - time_of_validity -> GPS_DELAY_MS
  baro pressure (Pa), temp (K)    BARO Press (Pa), Temp (degC * 100); Alt, AltAMSL the ISA pressure altitudes
  diff_pressure pressure (Pa)     ARSP DiffPress = p * 2 / (ARSPD_RATIO * rho0) (Pa; ArduPilot's EAS is
                                    sqrt(DiffPress * ARSPD_RATIO), the estimator's sqrt(2 p / rho0), rho0 the ISA's
                                    sea-level density, tern/atmosphere.hpp); Airspeed that EAS
  mag  field (T), body FRD        MAG MagX/Y/Z (mGauss = 1e-7 T, int16)
  actuators delta_a/e/r (rad),    RCOU C1..C4 (us) through PARM SERVOn_FUNCTION/MIN/TRIM/MAX/REVERSED (SERVOS):
       delta_t (0..1)               ArduPilot's roll right, nose up, nose right commands u = delta_a / max_a,
                                    -delta_e / max_e, -delta_r / max_r (the uavbook's signs undone, docs/sensor-log.md)
                                    as pulses, trim + (max - trim) u above the trim, trim + (trim - min) u below,
                                    u negated on a REVERSED channel; throttle min + (max - min) delta_t; max_a/e/r:
                                    the aircraft file's servos.max_delta_a/e/r (`tern import --max-deflection`)

The installation goes into the parameters ArduPilot keeps it in: INS_POS1_X/Y/Z (imu_position), GPS_POS1_X/Y/Z
(gnss_antenna_position), EK3_HGT_DELAY (baro_delay), from the log's config.yaml where it has an estimator_ekf.
Times: TimeUS = BOOT_US + stamp (us); `tern import dataflash` starts its clock at the earliest message, so the
imported log's time is the source's less `origin_s` (write() returns it). No reference (ATT, POS) is written:
a rewritten log has none. A row with a non-finite value is skipped and counted (ArduPilot logs no NaN).
`--check BIN_DIR` imports the .bin with BIN_DIR/tern and compares every sensor with the source within the
format's resolution (check()).
"""
import argparse
import calendar
import csv
import datetime
import math
import os
import shutil
import struct
import subprocess
import sys

import sdk_constants

# ---- the format (LogStructure.h); tests/fuzz/make_dataflash_seeds.py imports these

HEADER = b"\xa3\x95"
SIZES = {"b": 1, "B": 1, "M": 1, "h": 2, "H": 2, "c": 2, "C": 2, "i": 4, "I": 4, "e": 4, "E": 4, "L": 4, "f": 4,
         "n": 4, "q": 8, "Q": 8, "d": 8, "N": 16, "Z": 64, "a": 64}
PACK = {"b": "b", "B": "B", "M": "B", "h": "h", "H": "H", "c": "h", "C": "H", "i": "i", "I": "I", "e": "i", "E": "I",
        "L": "i", "f": "f", "q": "q", "Q": "Q", "d": "d"}
SCALE = {"c": 100, "C": 100, "e": 100, "E": 100, "L": 1e7}

# ArduPlane 4.5's messages as `tern import dataflash` reads them: type id (any id works: the FMT says), name,
# format characters, labels. The order is the FMTs' order in the fuzz seeds.
ARDUPLANE_45 = [
    (64, "PARM", "QNff", "TimeUS,Name,Value,Default"),
    (91, "MSG", "QZ", "TimeUS,Message"),
    (130, "IMU", "QBffffffIIfBBHH", "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,EG,EA,T,GH,AH,GHz,AHz"),
    (131, "GPS", "QBBIHBcLLeffffB", "TimeUS,I,Status,GMS,GWk,NSats,HDop,Lat,Lng,Alt,Spd,GCrs,VZ,Yaw,U"),
    (132, "GPA", "QBCCCCfBIHH", "TimeUS,I,VDop,HAcc,VAcc,SAcc,YAcc,VV,SMS,Delta,Und"),
    (133, "BARO", "QBfffcfIffB", "TimeUS,I,Alt,AltAMSL,Press,Temp,CRt,SMS,Offset,GndTemp,H"),
    (134, "ARSP", "QBffcffBBffB", "TimeUS,I,Airspeed,DiffPress,Temp,RawPress,Offset,U,H,Hp,TR,Pri"),
    (135, "MAG", "QBhhhhhhhhhBI", "TimeUS,I,MagX,MagY,MagZ,OfsX,OfsY,OfsZ,MOX,MOY,MOZ,Health,S"),
    (136, "RCOU", "QHHHHHHHHHHHHHH", "TimeUS,C1,C2,C3,C4,C5,C6,C7,C8,C9,C10,C11,C12,C13,C14"),
    (137, "ATT", "QccccCCCCB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF"),
    (138, "POS", "QLLfff", "TimeUS,Lat,Lng,Alt,RelHomeAlt,RelOriginAlt"),
    (139, "SIDS", "QBfffffff", "TimeUS,Ax,Mag,FSt,FSp,TFin,TC,TR,TFout"),
    (140, "SIDD", "Qfffffffff", "TimeUS,Time,Targ,F,Gx,Gy,Gz,Ax,Ay,Az"),
]
TYPE = {name: kind for kind, name, _, _ in ARDUPLANE_45}


class Log:
    """A DataFlash byte stream: FMT messages, then messages packed by their types' format characters."""

    def __init__(self):
        self.out = bytearray()
        self.formats = {}
        self.fmt(128, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns")

    def fmt(self, kind, name, format, labels):
        self.formats[kind] = format
        length = 3 + sum(SIZES[c] for c in format)
        body = struct.pack("<BB4s16s64s", kind, length, name.encode(), format.encode(), labels.encode())
        self.out += HEADER + bytes([128]) + body

    def define(self, layouts=ARDUPLANE_45):
        for kind, name, format, labels in layouts:
            self.fmt(kind, name, format, labels)

    def pack(self, kind, *values):
        """The message's bytes: values in the format's units (c C e E L scaled here), integers rounded."""
        body = bytearray()
        for c, v in zip(self.formats[kind], values, strict=True):
            if c in "nNZ":
                body += v.encode().ljust(SIZES[c], b"\0")
            else:
                x = v * SCALE.get(c, 1)
                body += struct.pack("<" + PACK[c], x if c in "fd" else int(round(x)))
        return HEADER + bytes([kind]) + bytes(body)

    def msg(self, kind, *values):
        self.out += self.pack(kind, *values)


# ---- the conventions of the bench's logs (stated here, written into the .bin as PARMs)

BOOT_US = 90_000_000  # us: the log's first sample 90 s after ArduPilot's boot (TimeUS counts from boot)
FIRMWARE = "ArduPlane V4.5.7 (tern bench/dataflash_log.py)"
ARSPD_RATIO = 1.9936  # ArduPilot's default
# kg/m^3: ArduPilot's and tern's sea-level density (EAS), and the ISA's barometric formula (Pa, 1/m, -)
RHO0 = sdk_constants.constant("atmosphere.hpp", "kIsaSeaLevelDensity")
P0 = sdk_constants.constant("atmosphere.hpp", "kIsaSeaLevelPressure")
ISA_K = sdk_constants.constant("atmosphere.hpp", "kIsaPressureLapse")
ISA_N = sdk_constants.constant("atmosphere.hpp", "kIsaPressureExponent")
KELVIN = sdk_constants.constant("atmosphere.hpp", "kZeroCelsius")
GPS_EPOCH_UNIX = 315964800  # 1980-01-06 00:00:00 UTC
LEAP_SECONDS = 18  # GPS - UTC since 2017
START_UTC = "12:00:00"  # the log's first sample on its date (only the date is read back)
# channel: (role, SERVOn_FUNCTION, MIN, TRIM, MAX, REVERSED): a trim off centre on the elevator (two spans),
# a reversed rudder
SERVOS = {
    1: ("aileron", 4, 1000, 1500, 2000, 0),
    2: ("elevator", 19, 1100, 1520, 1900, 0),
    3: ("throttle", 70, 1000, 1000, 2000, 0),
    4: ("rudder", 21, 1100, 1500, 1900, 1),
}


def float32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def read_table(path):
    """A sensor-log CSV as (names without units, rows of floats; '' and 'nan' as NaN)."""
    with open(path, newline="") as f:
        rows = csv.reader(f)
        names = [h.split(" [")[0] for h in next(rows)]
        return names, [[float(x) if x not in ("", "nan") else math.nan for x in r] for r in rows]


def table(log_dir, name):
    """{column: list} of topics/NAME.csv, or None when the log has no such table."""
    path = os.path.join(log_dir, "topics", f"{name}.csv")
    if not os.path.exists(path):
        return None
    names, rows = read_table(path)
    return {n: [r[k] for r in rows] for k, n in enumerate(names)}


def time_us(stamp_ns):
    """TimeUS (us since boot) of a sensor-log stamp (ns on the log's clock)."""
    return BOOT_US + int(round(stamp_ns / 1000.0))


def gps_week_ms(date, t_s):
    """GPS week and millisecond of the week of `t_s` s after START_UTC on `date` (ISO, UTC)."""
    unix = calendar.timegm(datetime.datetime.fromisoformat(f"{date}T{START_UTC}").timetuple()) + t_s
    gps = unix - GPS_EPOCH_UNIX + LEAP_SECONDS
    week = int(gps // 604800)
    return week, int(round((gps - week * 604800) * 1000))


def isa_altitude(p_pa):
    """m: the ISA troposphere's pressure altitude (docs/sensor-log.md, baro)."""
    return (1.0 - (p_pa / P0) ** (1.0 / ISA_N)) / ISA_K


# ---- what the log's own files say: the aircraft's servo throws, the date, the installation


def load_yaml(path):
    import yaml  # Debian's python3-yaml; imported here so that the fuzz seed maker needs the standard library only

    with open(path) as f:
        return yaml.safe_load(f)


def flight_config(log_dir):
    """The log's config.yaml (a tern flight's, kept by foreign_log.py), or {}."""
    path = os.path.join(log_dir, "config.yaml")
    return (load_yaml(path) or {}) if os.path.exists(path) else {}


def max_deflection(aircraft_file):
    """rad: the full aileron, elevator and rudder throws (servos.max_delta_a/e/r; 45 deg where the file has none)."""
    servos = (load_yaml(aircraft_file) or {}).get("servos", {}) or {}
    return [float(servos.get(k, math.radians(45.0))) for k in ("max_delta_a", "max_delta_e", "max_delta_r")]


def flight_date(log_dir):
    """ISO date of the flight: sensor_log.yaml's `date`, else the simulator's `date` parameter in config.yaml."""
    meta_path = os.path.join(log_dir, "sensor_log.yaml")
    meta = load_yaml(meta_path) if os.path.exists(meta_path) else {}
    if meta and meta.get("date"):
        return str(meta["date"])
    for p in flight_config(log_dir).get("plugins", []) or []:
        if (p.get("params") or {}).get("date"):
            return str(p["params"]["date"])
    return None


def installation(log_dir):
    """The first estimator_ekf instance's imu_position, gnss_antenna_position (m, body FRD from the CG) and
    baro_delay (s) in config.yaml: what ArduPilot keeps in INS_POS1_*, GPS_POS1_* and EK3_HGT_DELAY."""
    for p in flight_config(log_dir).get("plugins", []) or []:
        if p.get("plugin") == "estimator_ekf":
            params = p.get("params") or {}
            return {k: params[k] for k in ("imu_position", "gnss_antenna_position", "baro_delay") if k in params}
    return {}


def gnss_delay_ms(gnss):
    """ms: the median of stamp - time_of_validity over the fixes that give their epoch (None: none do). A DataFlash
    GPS message holds when ArduPilot processed the fix; the receiver's lag is the parameter GPS_DELAY_MS."""
    lags = sorted(s - v for s, v in zip(gnss["stamp"], gnss.get("time_of_validity", [])) if v > 0)
    return int(round(lags[len(lags) // 2] / 1e6)) if lags else None


def parameters(log_dir, gnss):
    """PARM name -> value: the servo outputs (SERVOS), ARSPD_RATIO, GPS_DELAY_MS, the installation."""
    out = {}
    for ch, (_, function, lo, trim, hi, reversed_) in SERVOS.items():
        out.update({f"SERVO{ch}_FUNCTION": function, f"SERVO{ch}_MIN": lo, f"SERVO{ch}_TRIM": trim, f"SERVO{ch}_MAX": hi,
                    f"SERVO{ch}_REVERSED": reversed_})
    out["ARSPD_RATIO"] = ARSPD_RATIO
    out["AHRS_ORIENTATION"] = 0
    delay = gnss_delay_ms(gnss) if gnss else None
    if delay:
        out["GPS_DELAY_MS"] = delay
    where = installation(log_dir)
    for prefix, key in (("INS_POS1", "imu_position"), ("GPS_POS1", "gnss_antenna_position")):
        if key in where:
            out.update({f"{prefix}_{axis}": float(v) for axis, v in zip("XYZ", where[key])})
    if "baro_delay" in where:
        out["EK3_HGT_DELAY"] = round(1000.0 * float(where["baro_delay"]))
    return out


# ---- one function per message: a sensor-log row as the values of its DataFlash message


def imu_values(t_us, r, rate_hz):
    """IMU: rad/s and m/s^2 in body FRD as logged, T degC; healthy, at rate_hz."""
    return (t_us, 0, r["gyro_x"], r["gyro_y"], r["gyro_z"], r["accel_x"], r["accel_y"], r["accel_z"], 0, 0,
            r.get("temperature", KELVIN + 15.0) - KELVIN, 1, 1, rate_hz, rate_hz)


def gps_status(fix_type):
    """AP_GPS::GPS_Status of a sensor-log fix type: 3-D 3, 2-D 2, none or dead reckoning 1 (NO_FIX)."""
    return 3 if fix_type == 3 else 2 if fix_type == 2 else 1


def gps_values(t_us, r, week, week_ms):
    """GPS: Lat/Lng deg, Alt m MSL, Spd m/s and GCrs deg (0..360 from true north) of the NED ground velocity, VZ
    m/s down."""
    course = math.degrees(math.atan2(r["vel_e"], r["vel_n"])) % 360.0
    return (t_us, 0, gps_status(r["fix_type"]), week_ms, week, int(r["num_sats"]), r.get("hdop", 0.0), r["lat"], r["lon"],
            r["alt"], math.hypot(r["vel_n"], r["vel_e"]), course, r["vel_d"], 0.0, 1)


def gpa_values(t_us, r, delta_ms):
    """GPA (the GPS message's TimeUS): VDop, HAcc/VAcc m, SAcc m/s (0: not reported), VV 1 (a down velocity)."""
    return (t_us, 0, r.get("vdop", 0.0), r.get("h_acc", 0.0), r.get("v_acc", 0.0), r.get("s_acc", 0.0), 0.0, 1,
            t_us // 1000, delta_ms, 0)


def baro_values(t_us, r, p_ground):
    """BARO: Press Pa, Temp degC; Alt the ISA pressure altitude above the first sample's, AltAMSL against 1013.25 hPa."""
    temp = r.get("temperature", KELVIN + 15.0) - KELVIN
    return (t_us, 0, isa_altitude(r["pressure"]) - isa_altitude(p_ground), isa_altitude(r["pressure"]), r["pressure"], temp,
            0.0, t_us // 1000, 0.0, temp, 1)


def arsp_values(t_us, r, ratio):
    """ARSP: DiffPress Pa such that ArduPilot's EAS sqrt(DiffPress * ratio) is the ideal pitot's sqrt(2 p / RHO0)."""
    dp = r["pressure"] * 2.0 / (ratio * RHO0)
    return (t_us, 0, math.sqrt(max(dp * ratio, 0.0)), dp, r.get("temperature", KELVIN + 15.0) - KELVIN, dp, 0.0, 1, 1,
            1.0, 0.0, 0)


def mag_values(t_us, r):
    """MAG: MagX/Y/Z mGauss (1e-7 T) in body FRD, offsets removed (0)."""
    return (t_us, 0, r["field_x"] * 1e7, r["field_y"] * 1e7, r["field_z"] * 1e7, 0, 0, 0, 0, 0, 0, 1, 0)


def pulse_from_angle(u, servo):
    """us: ArduPilot's scaled surface output u (-1..1; its sign the servo's before REVERSED) as a pulse: trim +
    (max - trim) u above the trim, trim + (trim - min) u below."""
    _, _, lo, trim, hi, reversed_ = servo
    u = -u if reversed_ else u
    return trim + (hi - trim) * u if u >= 0.0 else trim + (trim - lo) * u


def pulse_from_range(u, servo):
    """us: a throttle 0..1 as a pulse, min + (max - min) u (1 - u when REVERSED)."""
    _, _, lo, _, hi, reversed_ = servo
    return lo + (hi - lo) * (1.0 - u if reversed_ else u)


def normalised(r, throws):
    """ArduPilot's roll right, nose up, nose right (-1..1) and throttle (0..1) of the uavbook's deflections (rad):
    delta_a = +roll max_a, delta_e = -pitch max_e, delta_r = -yaw max_r (docs/sensor-log.md, actuators)."""
    return {"aileron": r["delta_a"] / throws[0], "elevator": -r["delta_e"] / throws[1], "rudder": -r["delta_r"] / throws[2],
            "throttle": r["delta_t"]}


def rcou_values(t_us, r, throws):
    """RCOU: C1..C14 (us; 0 where no output is mapped), each surface's command clamped to its full throw; and
    whether any was clamped."""
    u = normalised(r, throws)
    pwm, clamped = [0] * 14, False
    for ch, servo in SERVOS.items():
        lo, hi = (0.0, 1.0) if servo[0] == "throttle" else (-1.0, 1.0)
        x = min(max(u[servo[0]], lo), hi)
        clamped = clamped or x != u[servo[0]]
        pwm[ch - 1] = pulse_from_range(x, servo) if servo[0] == "throttle" else pulse_from_angle(x, servo)
    return (t_us, *pwm), clamped


# ---- the log


def rows(tab):
    """The table's rows as dicts of column -> value."""
    names = list(tab)
    return (dict(zip(names, values)) for values in zip(*tab.values()))


def finite(r):
    return all(math.isfinite(v) for k, v in r.items() if k not in ("t", "stamp"))


def sensor_messages(log, log_dir, throws, date, ratio):
    """(TimeUS, rank, bytes) of every sensor and command row, and the counts of rows skipped (non-finite) and of
    commands clamped to their throws. rank keeps a GPS message before its GPA at the same TimeUS."""
    out, skipped, clamped = [], {}, 0
    imu, gnss = table(log_dir, "imu"), table(log_dir, "gnss")
    if imu is None:
        raise SystemExit(f"dataflash_log: {log_dir}: no topics/imu.csv")
    span = (imu["stamp"][-1] - imu["stamp"][0]) / 1e9
    rate = int(round((len(imu["stamp"]) - 1) / span)) if span > 0 else 0
    tables = [("imu", imu), ("gnss", gnss)] + [(n, table(log_dir, n)) for n in ("baro", "diff_pressure", "mag", "actuators")]
    t0 = imu["stamp"][0] / 1e9
    for name, tab in tables:
        if tab is None:
            continue
        previous_ms, p_ground = None, None
        for r in rows(tab):
            if not finite(r):
                skipped[name] = skipped.get(name, 0) + 1
                continue
            t = time_us(r["stamp"])
            if name == "imu":
                out.append((t, 0, log.pack(TYPE["IMU"], *imu_values(t, r, rate))))
            elif name == "gnss":
                week, week_ms = gps_week_ms(date, r["stamp"] / 1e9 - t0)
                out.append((t, 1, log.pack(TYPE["GPS"], *gps_values(t, r, week, week_ms))))
                out.append((t, 2, log.pack(TYPE["GPA"], *gpa_values(t, r, t // 1000 - previous_ms if previous_ms else 0))))
                previous_ms = t // 1000
            elif name == "baro":
                p_ground = r["pressure"] if p_ground is None else p_ground
                out.append((t, 3, log.pack(TYPE["BARO"], *baro_values(t, r, p_ground))))
            elif name == "diff_pressure":
                out.append((t, 4, log.pack(TYPE["ARSP"], *arsp_values(t, r, ratio))))
            elif name == "mag":
                out.append((t, 5, log.pack(TYPE["MAG"], *mag_values(t, r))))
            else:
                values, c = rcou_values(t, r, throws)
                clamped += c
                out.append((t, 6, log.pack(TYPE["RCOU"], *values)))
    return out, skipped, clamped


def write(log_dir, out_bin, throws, date):
    """Writes the sensor log LOG_DIR as the DataFlash log OUT_BIN (module docstring). throws: rad, the full aileron,
    elevator and rudder deflections; date: ISO UTC date of the flight. Returns what was done: origin_s (s: the
    source's time of the imported log's 0, its earliest row), the parameters, the rows skipped, the commands clamped."""
    if date is None:
        raise SystemExit(f"dataflash_log: {log_dir}: no date in sensor_log.yaml or config.yaml: give --date")
    log = Log()
    log.define()
    params = parameters(log_dir, table(log_dir, "gnss"))
    ratio = float32(params["ARSPD_RATIO"])  # what the importer reads back from the PARM's float
    messages, skipped, clamped = sensor_messages(log, log_dir, throws, date, ratio)
    messages.sort(key=lambda m: (m[0], m[1]))
    header_us = BOOT_US - 1_000_000  # the firmware line and the parameters, before the first sample
    log.msg(TYPE["MSG"], header_us, FIRMWARE)
    for name, value in params.items():
        log.msg(TYPE["PARM"], header_us, name, value, 0.0)
    for _, _, data in messages:
        log.out += data
    with open(out_bin, "wb") as f:
        f.write(log.out)
    origin_us = messages[0][0] if messages else BOOT_US
    return {"origin_s": (origin_us - BOOT_US) / 1e6, "parameters": params, "skipped_rows": skipped,
            "clamped_commands": clamped, "max_deflection": throws, "date": date, "bytes": len(log.out)}


# ---- back through `tern import dataflash`, and the round trip's check


def import_bin(tern, out_bin, out_dir, throws):
    """`tern import dataflash OUT_BIN OUT_DIR --max-deflection A E R`; its printed account."""
    argv = [tern, "import", "dataflash", out_bin, out_dir, "--max-deflection"] + [f"{x:.9g}" for x in throws]
    p = subprocess.run(argv, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"dataflash_log: {' '.join(argv)} failed ({p.returncode}):\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    return p.stdout + p.stderr


def carry_over(src_dir, imported_dir, origin_s):
    """What a DataFlash log does not hold but its user states beside it: the estimator configuration (the source's
    config.yaml, as foreign_log.py keeps it) and the airborne window (the source's, on the imported clock)."""
    if os.path.exists(os.path.join(src_dir, "config.yaml")):
        shutil.copyfile(os.path.join(src_dir, "config.yaml"), os.path.join(imported_dir, "config.yaml"))
    meta_path = os.path.join(src_dir, "sensor_log.yaml")
    window = (load_yaml(meta_path) or {}).get("airborne") if os.path.exists(meta_path) else None
    if window:
        start, end = max(0.0, float(window[0]) - origin_s), float(window[1]) - origin_s
        with open(os.path.join(imported_dir, "sensor_log.yaml"), "a") as f:
            f.write(f"# declared beside the .bin (bench/dataflash_log.py): the source log's airborne window, less {origin_s:g} s\n"
                    f"airborne: [{start:.6f}, {end:.6f}]\n")


def read_back(tern, src_dir, out_bin, imported_dir, origin_s, throws):
    """The .bin back through `tern import dataflash` into imported_dir (made anew), what its user states beside it
    carried over (carry_over), and the round trip checked against the source: (tern's account, report, ok)."""
    shutil.rmtree(imported_dir, ignore_errors=True)
    account = import_bin(tern, out_bin, imported_dir, throws)
    carry_over(src_dir, imported_dir, origin_s)
    report, ok = check(src_dir, imported_dir, origin_s, throws)
    return account, report, ok


def resolutions(throws):
    """(table, column) -> (absolute, relative) tolerance of the round trip: half the format's step (float32: half
    an ulp, 6e-8 relative; c C e: 0.005; L: 0.5e-7 deg; MAG: 0.5 mGauss; RCOU: half a microsecond of the
    channel's shorter span times its throw), widened by the conversions' own float rounding."""
    f32 = (1e-12, 1.2e-7)
    span = {role: min(trim - lo, hi - trim) if role != "throttle" else hi - lo for role, _, lo, trim, hi, _ in SERVOS.values()}
    res = {("imu", c): f32 for c in ("accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z")}
    res[("imu", "temperature")] = (1e-5, 0.0)
    res.update({("gnss", "lat"): (0.5e-7 + 1e-12, 0.0), ("gnss", "lon"): (0.5e-7 + 1e-12, 0.0), ("gnss", "alt"): (0.005 + 1e-9, 0.0),
                ("gnss", "vel_n"): (2e-5, 0.0), ("gnss", "vel_e"): (2e-5, 0.0), ("gnss", "vel_d"): f32,
                ("gnss", "fix_type"): (0.0, 0.0), ("gnss", "num_sats"): (0.0, 0.0)})
    res.update({("gnss", c): (0.005 + 1e-9, 0.0) for c in ("h_acc", "v_acc", "s_acc", "hdop", "vdop")})
    res.update({("baro", "pressure"): f32, ("baro", "temperature"): (0.005 + 1e-9, 0.0),
                ("diff_pressure", "pressure"): (1e-12, 2.4e-7), ("diff_pressure", "temperature"): (0.005 + 1e-9, 0.0)})
    res.update({("mag", c): (0.5e-7 + 1e-15, 0.0) for c in ("field_x", "field_y", "field_z")})
    for col, role, k in (("delta_a", "aileron", 0), ("delta_e", "elevator", 1), ("delta_r", "rudder", 2)):
        res[("actuators", col)] = (0.5 / span[role] * throws[k] + 1e-12, 0.0)
    res[("actuators", "delta_t")] = (0.5 / span["throttle"] + 1e-12, 0.0)
    return res


def check(src_dir, imported_dir, origin_s, throws):
    """The round trip: every row of every sensor and command table back, at its time less origin_s (within half a
    microsecond), every column within resolutions(). Returns {table: {"rows": [source, imported], column:
    {"max_error", "tolerance_used" (the largest error over its tolerance)}}} and whether all held. Not compared:
    gnss time_of_validity (the format has none: GPS_DELAY_MS), actuators brake (no ArduPilot output)."""
    res, report, ok = resolutions(throws), {}, True
    for name in ("imu", "gnss", "baro", "diff_pressure", "mag", "actuators"):
        a, b = table(src_dir, name), table(imported_dir, name)
        if a is None:
            continue
        keep = [i for i, r in enumerate(rows(a)) if finite(r)]
        entry = report[name] = {"rows": [len(keep), len(b["t"]) if b else 0]}
        if not b or len(b["t"]) != len(keep):
            ok = False
            continue
        worst_dt = max(abs(b["stamp"][j] - (a["stamp"][i] - origin_s * 1e9)) for j, i in enumerate(keep))
        entry["stamp_max_error_ns"] = worst_dt
        ok = ok and worst_dt <= 500.0
        for (tab, col), (tol_abs, tol_rel) in res.items():
            if tab != name or col not in a:
                continue
            errs = [(abs(b[col][j] - a[col][i]), tol_abs + tol_rel * abs(a[col][i])) for j, i in enumerate(keep)]
            worst = max(e for e, _ in errs)
            used = max(e / t if t > 0 else (0.0 if e == 0 else math.inf) for e, t in errs)
            entry[col] = {"max_error": worst, "tolerance_used": used}
            ok = ok and used <= 1.0
    return report, ok


def check_lines(report):
    lines = []
    for name, entry in report.items():
        cols = ", ".join(f"{c} {v['max_error']:.3g} ({v['tolerance_used']:.2f})" for c, v in entry.items() if isinstance(v, dict))
        lines.append(f"  {name}: rows {entry['rows'][0]} -> {entry['rows'][1]}, stamps within "
                     f"{entry.get('stamp_max_error_ns', math.nan):.0f} ns; {cols}")
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("log", help="a sensor log directory (topics/*.csv, sensor_log.yaml)")
    ap.add_argument("out", help="the DataFlash file to write (.bin)")
    ap.add_argument("--aircraft", help="the aircraft file whose servos.max_delta_a/e/r scale the commands (default: "
                                       "config.yaml's aircraft)")
    ap.add_argument("--date", help="the flight's UTC date, YYYY-MM-DD (default: sensor_log.yaml's, else config.yaml's)")
    ap.add_argument("--check", metavar="BIN_DIR", help="import the .bin with BIN_DIR/tern into OUT.imported/ and compare")
    a = ap.parse_args()
    aircraft = a.aircraft or flight_config(a.log).get("aircraft")
    if not aircraft:
        raise SystemExit("dataflash_log: give --aircraft (the log has no config.yaml naming one)")
    throws = max_deflection(aircraft)
    done = write(a.log, a.out, throws, a.date or flight_date(a.log))
    print(f"dataflash_log: {a.out}: {done['bytes']} bytes; the imported log's 0 is {done['origin_s']:.6f} s of the source's; "
          f"--max-deflection {' '.join(f'{x:.9g}' for x in throws)}; rows skipped {done['skipped_rows'] or 'none'}; "
          f"commands clamped {done['clamped_commands']}")
    if a.check:
        imported = os.path.splitext(a.out)[0] + ".imported"
        account, report, ok = read_back(os.path.join(a.check, "tern"), a.log, a.out, imported, done["origin_s"], throws)
        print(account, end="")
        print("\n".join(["round trip (column max error (share of its tolerance used)):"] + check_lines(report)))
        print("round trip: " + ("every row and value back within the format's resolution" if ok else "FAILED"))
        sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
