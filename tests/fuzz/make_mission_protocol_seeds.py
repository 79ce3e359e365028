#!/usr/bin/env python3
"""Writes the seeds of fuzz_mission_protocol: sessions of a ground station with tern's mission protocol,
as the target reads them: records [op][flags][payload], op 0 MISSION_COUNT, 1 MISSION_ITEM_INT,
2 MISSION_REQUEST_LIST, 3 MISSION_REQUEST_INT, 4 MISSION_REQUEST, 5 MISSION_CLEAR_ALL,
6 MISSION_SET_CURRENT, 7 MISSION_ACK (the payload in common.xml's wire layout, full length), 8 a
call of the link (flags % 4: 0 fly_from(seq), 1 keep_mission, 2 on_tick, 3 current_seq; a uint16
seq). Flags bit 0 addresses the message to the vehicle. Sessions: QGroundControl's upload of a
mission (takeoff, waypoint, loiter, speed change, land around Zurich), a geofence (an inclusion
polygon and an exclusion circle) and rally points, each read back; set current, MISSION_START and
clears; and hostile ones: MISSION_COUNT 65535, unknown mission types, NaN parameters, items out of
order or of another list, requests past the end.

  make_mission_protocol_seeds.py OUT_DIR
"""
import os
import struct
import sys

from seed_files import write_seeds

NAN = float("nan")
MISSION, FENCE, RALLY, ALL = 0, 1, 2, 255
LENGTH = {0: 9, 1: 38, 2: 3, 3: 5, 4: 5, 5: 3, 6: 4, 7: 8}  # the messages' full wire lengths (crc_extra_mission.txt)


def rec(op, payload=b"", flags=1):
    if op in LENGTH:
        payload = payload.ljust(LENGTH[op], b"\0")
    return bytes([op, flags]) + payload


def count(n, mission_type=MISSION):
    return rec(0, struct.pack("<HBBB", n, 1, 1, mission_type))


def item(seq, command, frame, lat, lon, z, p1=0.0, p2=0.0, p3=0.0, p4=NAN, mission_type=MISSION):
    return rec(1, struct.pack("<ffffiifHHBBBBBB", p1, p2, p3, p4, round(lat * 1e7), round(lon * 1e7), z, seq, command, 1, 1, frame, 0, 1,
                              mission_type))


def request_list(mission_type=MISSION):
    return rec(2, struct.pack("<BBB", 1, 1, mission_type))


def request_int(seq, mission_type=MISSION):
    return rec(3, struct.pack("<HBBB", seq, 1, 1, mission_type))


def request(seq, mission_type=MISSION):
    return rec(4, struct.pack("<HBBB", seq, 1, 1, mission_type))


def clear(mission_type=MISSION):
    return rec(5, struct.pack("<BBB", 1, 1, mission_type))


def set_current(seq):
    return rec(6, struct.pack("<HBB", seq, 1, 1))


def ack(result=0, mission_type=MISSION):
    return rec(7, struct.pack("<BBBB", 1, 1, result, mission_type))


def call(kind, seq=0):
    return rec(8, struct.pack("<H", seq), flags=kind)


def read_back(n, mission_type=MISSION):
    return request_list(mission_type) + b"".join(request_int(i, mission_type) for i in range(n)) + ack(0, mission_type)


def mission():
    return [item(0, 22, 6, 47.3890, 8.0340, 40.0, p1=10.0),  # takeoff
            item(1, 16, 6, 47.3905, 8.0362, 60.0),  # waypoint
            item(2, 18, 6, 47.3920, 8.0340, 60.0, p1=2.0, p3=-80.0),  # loiter turns
            item(3, 178, 2, 0.0, 0.0, 0.0, p1=0.0, p2=15.0, p3=-1.0, p4=0.0),  # change speed
            item(4, 21, 6, 47.3890, 8.0340, 0.0, p4=90.0)]  # land


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    m = mission()
    fence = [item(i, 5001, 5, lat, lon, 0.0, p1=4.0, p4=0.0, mission_type=FENCE)
             for i, (lat, lon) in enumerate([(47.394, 8.028), (47.394, 8.040), (47.384, 8.040), (47.384, 8.028)])]
    fence.append(item(4, 5004, 5, 47.3905, 8.0362, 0.0, p1=50.0, p4=0.0, mission_type=FENCE))
    rally = [item(i, 5100, 6, lat, lon, 80.0, p4=0.0, mission_type=RALLY) for i, (lat, lon) in enumerate([(47.391, 8.036), (47.387, 8.031)])]
    seeds = {
        "upload_mission.bin": count(5) + b"".join(m) + read_back(5),
        "upload_fence.bin": count(5, FENCE) + b"".join(fence) + read_back(5, FENCE),
        "upload_rally.bin": count(2, RALLY) + b"".join(rally) + read_back(2, RALLY),
        "read_back_config.bin": read_back(0) + read_back(5, FENCE) + read_back(1, RALLY) + request(0, FENCE),
        "set_current_start_clear.bin": count(5) + b"".join(m) + set_current(1) + call(0, 2) + call(1) + call(3) + call(2) +
        clear(FENCE) + clear(ALL) + read_back(0),
        # hostile: a count past the limit, unknown types, NaN parameters, items out of order and of
        # another list, requests past the end, messages not addressed to the vehicle
        "hostile.bin": count(65535) + count(3, 7) + request_list(9) + clear(200) + count(3) + m[1] + m[0] +
        item(1, 16, 6, 47.39, 8.03, 60.0, p1=NAN, p2=NAN, p3=NAN) + count(2) + m[0] + fence[0] + request_int(65535) + request(7, 3) +
        set_current(65535) + call(0, 65535) + rec(0, struct.pack("<HBBB", 2, 9, 9, MISSION), flags=0) + ack(15, 1),
    }
    write_seeds(out, seeds)


if __name__ == "__main__":
    main()
