#!/usr/bin/env python3
"""Cuts small seeds for fuzz_ulog_reader out of a real ULog (PX4/pyulog's test logs, BSD-3-Clause,
/work/shared/reference/ulog_samples): the header, the flag bits, the formats of a few topics (with the
nested formats they name), a few info/parameter messages, and the first data messages of those
topics with a logged string, a sync and a dropout where the log has them. The messages are copied
byte for byte; only the selection is ours.

  make_ulog_seeds.py LOG.ulg OUT.ulg TOPIC [TOPIC ...] [--param NAME ...] [--rows N]

--param keeps the named parameters ('P' messages) besides the first six (fuzz_ulog_conversion's
seeds keep MAV_TYPE and the EKF2 delays and positions `tern import ulog` maps); --rows keeps N data
messages per topic (default 3).

  make_ulog_seeds.py --px4-control-allocation OUT.ulg

writes instead a small log of PX4 v1.13+'s control allocation, which the samples predate (as
tests/real_data/test_ulog.cpp's UlogBytes writes one): a fixed wing's sensor_combined,
vehicle_gps_position (timestamp_sample, time_utc_usec), actuator_servos and actuator_motors, and
the parameters MAV_TYPE, CA_AIRFRAME, CA_ROTOR_COUNT, CA_SV_CS_COUNT, CA_SV_CS<i>_TRQ_R/P/Y,
EKF2_GPS_DELAY.
"""
import struct
import sys


def messages(data):
    pos = 16
    while pos + 3 <= len(data):
        size, kind = struct.unpack_from("<HB", data, pos)
        yield chr(kind), data[pos:pos + 3 + size], data[pos + 3:pos + 3 + size]
        pos += 3 + size


def control_allocation(out):
    def msg(kind, payload):
        return struct.pack("<HB", len(payload), ord(kind)) + payload

    def param(type_, name, fmt, value):
        key = f"{type_} {name}".encode()
        return msg("P", bytes([len(key)]) + key + struct.pack(fmt, value))

    body = b"ULog\x01\x12\x35\x01" + struct.pack("<Q", 1_000_000)
    body += msg("F", b"sensor_combined:uint64_t timestamp;float[3] gyro_rad;float[3] accelerometer_m_s2")
    body += msg("F", b"vehicle_gps_position:uint64_t timestamp;uint64_t timestamp_sample;uint64_t time_utc_usec;int32_t lat;"
                     b"int32_t lon;int32_t alt;float eph;float epv;float vel_n_m_s;float vel_e_m_s;float vel_d_m_s;uint8_t fix_type;"
                     b"uint8_t satellites_used")
    body += msg("F", b"actuator_servos:uint64_t timestamp;uint64_t timestamp_sample;float[8] control")
    body += msg("F", b"actuator_motors:uint64_t timestamp;uint64_t timestamp_sample;float[4] control")
    for name, value in (("MAV_TYPE", 1), ("CA_AIRFRAME", 1), ("CA_ROTOR_COUNT", 1), ("CA_SV_CS_COUNT", 3)):
        body += param("int32_t", name, "<i", value)
    for i, trq in enumerate(((-0.5, 0.0, 0.0), (0.5, 0.0, 0.0), (0.0, 1.0, 0.0))):
        for axis, v in zip("RPY", trq):
            body += param("float", f"CA_SV_CS{i}_TRQ_{axis}", "<f", v)
    body += param("float", "EKF2_GPS_DELAY", "<f", 110.0)
    for msg_id, topic in enumerate((b"sensor_combined", b"vehicle_gps_position", b"actuator_servos", b"actuator_motors")):
        body += msg("A", b"\0" + struct.pack("<H", msg_id) + topic)
    for k in range(4):
        t = 1_004_000 + 4000 * k
        body += msg("D", struct.pack("<HQ6f", 0, t, 0.01, 0.0, 0.0, 0.0, 0.0, -9.8))
        body += msg("D", struct.pack("<HQQ4f", 3, t, t - 500, 0.6, 0.0, 0.0, 0.0))
        body += msg("D", struct.pack("<HQQ8f", 2, t + 1000, t - 500, -0.2, 0.2, 0.3, 0.0, 0.0, 0.0, 0.0, 0.0))
    body += msg("D", struct.pack("<HQQQiiifffffBB", 1, 1_010_000, 1_009_000, 1_531_929_211_000_000, 473_890_000, 80_340_000, 470_000,
                                 1.2, 1.8, 12.0, 3.0, -0.5, 3, 12))
    open(out, "wb").write(body)
    print(f"{out}: {len(body)} bytes")


def main():
    if sys.argv[1] == "--px4-control-allocation":
        return control_allocation(sys.argv[2])
    args, params, rows = sys.argv[3:], set(), 3
    while "--param" in args:
        i = args.index("--param")
        params.add(args[i + 1])
        del args[i:i + 2]
    if "--rows" in args:
        i = args.index("--rows")
        rows = int(args[i + 1])
        del args[i:i + 2]
    src, out, topics = sys.argv[1], sys.argv[2], set(args)
    data = open(src, "rb").read()
    formats = {}
    for kind, raw, payload in messages(data):
        if kind == "F":
            name, _, fields = payload.decode().partition(":")
            formats[name] = (raw, [f.split(" ")[0].split("[")[0] for f in fields.split(";") if f])
    needed, pending = [], list(topics)
    while pending:  # the topics' formats and every format nested in them
        name = pending.pop()
        if name in formats and name not in needed:
            needed.append(name)
            pending.extend(formats[name][1])
    kept = {"I": 4, "P": 6, "M": 2, "Q": 2, "L": 2, "C": 1, "S": 1, "O": 1}
    ids, per_id, body = set(), {}, bytearray(data[:16])
    for kind, raw, payload in messages(data):
        if kind == "B":
            body += raw
        elif kind == "F":
            if payload.decode().partition(":")[0] in needed:
                body += raw
        elif kind == "A":
            if payload[3:].decode() in topics:
                ids.add(struct.unpack_from("<H", payload, 1)[0])
                body += raw
        elif kind == "D":
            msg_id = struct.unpack_from("<H", payload, 0)[0]
            if msg_id in ids and per_id.get(msg_id, 0) < rows:
                per_id[msg_id] = per_id.get(msg_id, 0) + 1
                body += raw
        elif kind == "P" and payload[1:1 + payload[0]].decode(errors="replace").split(" ")[-1] in params:
            body += raw
        elif kept.get(kind, 0) > 0:
            kept[kind] -= 1
            body += raw
    open(out, "wb").write(body)
    print(f"{out}: {len(body)} bytes, formats {needed}, data messages {sum(per_id.values())}")


if __name__ == "__main__":
    main()
