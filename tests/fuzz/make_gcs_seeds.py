#!/usr/bin/env python3
"""Writes the seeds of fuzz_gcs_datagram: UDP datagrams a ground station sends tern (MAVLink 2,
common.xml), framed here from the wire layouts and CRC_EXTRA values of tests/mavlink/crc_extra_*.txt.

  make_gcs_seeds.py OUT_DIR
"""
import math
import os
import struct
import sys

from seed_files import write_seeds

CRC_EXTRA = {"HEARTBEAT": (0, 50), "PARAM_REQUEST_READ": (20, 214), "PARAM_REQUEST_LIST": (21, 159), "PARAM_SET": (23, 168),
             "MISSION_COUNT": (44, 221), "MISSION_CLEAR_ALL": (45, 232), "MISSION_ACK": (47, 153), "MISSION_ITEM_INT": (73, 38),
             "MISSION_REQUEST_LIST": (43, 132), "MISSION_SET_CURRENT": (41, 28), "COMMAND_LONG": (76, 152)}


def x25(data, crc=0xFFFF):
    for b in data:
        t = (b ^ crc) & 0xFF
        t = (t ^ (t << 4)) & 0xFF
        crc = ((crc >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4)) & 0xFFFF
    return crc


def frame(name, payload, seq, sysid=255, compid=190):
    msgid, extra = CRC_EXTRA[name]
    payload = payload.rstrip(b"\0") or b"\0"  # MAVLink 2 trims trailing zeros
    header = struct.pack("<BBBBBBB", len(payload), 0, 0, seq & 0xFF, sysid, compid, msgid & 0xFF) + struct.pack("<H", msgid >> 8)
    crc = x25(bytes([extra]), x25(header + payload))
    return b"\xfd" + header + payload + struct.pack("<H", crc)


def item(seq, command, frame_, lat, lon, z, p1=0.0, p2=0.0, p3=0.0, p4=float("nan")):
    return struct.pack("<ffffiifHHBBBBBB", p1, p2, p3, p4, round(lat * 1e7), round(lon * 1e7), z, seq, command, 1, 1, frame_, 0, 1, 0)


def main():
    out = sys.argv[1]
    hb = struct.pack("<IBBBBB", 0, 6, 8, 0, 4, 3)  # QGroundControl's heartbeat
    seeds = {
        "heartbeat.bin": frame("HEARTBEAT", hb, 0),
        "params.bin": frame("PARAM_REQUEST_LIST", struct.pack("<BB", 1, 1), 1)
        + frame("PARAM_REQUEST_READ", struct.pack("<hBB16s", -1, 1, 1, b"slc.roll_kp"), 2)
        + frame("PARAM_SET", struct.pack("<fBB16sB", 0.6, 1, 1, b"slc.roll_kp", 9), 3),
        # an upload as QGroundControl sends it (count, then the items as requested): takeoff,
        # a waypoint, a loiter, a speed change, land, around Zurich, GLOBAL_RELATIVE_ALT_INT
        "mission_upload.bin": frame("MISSION_COUNT", struct.pack("<HBBB", 5, 1, 1, 0), 4)
        + frame("MISSION_ITEM_INT", item(0, 22, 6, 47.3890, 8.0340, 40.0, p1=10.0), 5)
        + frame("MISSION_ITEM_INT", item(1, 16, 6, 47.3905, 8.0362, 60.0), 6)
        + frame("MISSION_ITEM_INT", item(2, 18, 6, 47.3920, 8.0340, 60.0, p1=2.0, p3=-80.0), 7)
        + frame("MISSION_ITEM_INT", item(3, 178, 2, 0.0, 0.0, 0.0, p1=0.0, p2=15.0, p3=-1.0, p4=0.0), 8)
        + frame("MISSION_ITEM_INT", item(4, 21, 6, 47.3890, 8.0340, 0.0, p4=90.0), 9),
        "mission_misc.bin": frame("MISSION_REQUEST_LIST", struct.pack("<BBB", 1, 1, 0), 10)
        + frame("MISSION_SET_CURRENT", struct.pack("<HBB", 2, 1, 1), 11)
        + frame("MISSION_ACK", struct.pack("<BBBB", 1, 1, 0, 0), 12)
        + frame("MISSION_CLEAR_ALL", struct.pack("<BBB", 1, 1, 0), 13),
        # MAV_CMD_MISSION_START (300) from item 1, then arm (400)
        "commands.bin": frame("COMMAND_LONG", struct.pack("<fffffffHBBB", 1, 0, 0, 0, 0, 0, 0, 300, 1, 1, 0), 14)
        + frame("COMMAND_LONG", struct.pack("<fffffffHBBB", 1, 0, 0, 0, 0, 0, 0, 400, 1, 1, 0), 15),
        # what else reaches the port: a MAVLink 1 heartbeat, noise, a frame cut short
        "mixed.bin": b"\xfe\x09\x00\xff\xbe\x00" + hb + b"\x00\x00" + b"noise\x00" + frame("HEARTBEAT", hb, 16)
        + frame("HEARTBEAT", hb, 17)[:8],
    }
    write_seeds(out, seeds)


if __name__ == "__main__":
    main()
