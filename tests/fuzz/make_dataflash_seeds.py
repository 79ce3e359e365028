#!/usr/bin/env python3
"""Writes small ArduPilot DataFlash logs (.bin) for fuzz_dataflash, from the format's spec
(ArduPilot's libraries/AP_Logger/LogStructure.h: every message 0xA3 0x95 type; FMT, type 128 of 89
bytes, defines each type's length, name, format characters and labels; c C e E are stored * 100 and L
as degrees * 1e7), with the messages and labels `tern import dataflash` reads, as ArduPlane 4.5 writes
them (tests/real_data/test_dataflash.cpp's DataflashBytes writes the same in C++). The encoder (Log) and
the layouts are bench/dataflash_log.py's, which writes whole flights with them:

  make_dataflash_seeds.py OUT_DIR

  plane.bin          PARM (SERVOn_*), MSG, IMU 400 Hz (two instances), GPS/GPA, BARO, ARSP, MAG,
                     RCOU, ATT, POS, SIDS and SIDD: a quarter of a second
  plane_garbage.bin  the same with bytes that are no message between messages, and a header of a
                     type no FMT defines
"""
import math
import sys
from pathlib import Path

# the encoder and ArduPlane 4.5's layouts, shared with the bench's DataFlash writer (one definition of each)
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench"))
from dataflash_log import Log  # noqa: E402


def plane(garbage=False):
    d = Log()
    d.define()  # PARM 64, MSG 91, IMU 130 .. SIDD 140: dataflash_log.ARDUPLANE_45
    t0 = 5_000_000
    d.msg(91, t0, "ArduPlane V4.5.7 (seed)")
    for name, value in [("SERVO1_FUNCTION", 4), ("SERVO2_FUNCTION", 19), ("SERVO3_FUNCTION", 70), ("SERVO5_FUNCTION", 21),
                        ("SERVO5_REVERSED", 1), ("SERVO2_TRIM", 1400), ("ARSPD_RATIO", 2.0), ("GPS_DELAY_MS", 150)]:
        d.msg(64, t0, name, value, 0.0)
    d.msg(139, t0, 11, 0.1, 0.5, 4.0, 0.0, 4.0, 1.0, 0.0)
    for k in range(100):
        t = t0 + 2500 * k
        d.msg(130, t, 0, 0.1 * math.sin(k / 40), 0.05, -0.02, 0.5, 0.1, -9.81, 0, 0, 41.25, 1, 1, 400, 400)
        d.msg(130, t, 1, 0.1, 0.05, -0.02, 0.5, 0.1, -9.81, 0, 0, 40.0, 1, 1, 400, 400)
        if garbage and k % 13 == 3:
            d.out += b"\x01\x02\xa3\x03garbage"
        if garbage and k == 50:
            d.out += b"\xa3\x95\xc8" + b"\x55" * 20
        if k % 8 == 0:
            d.msg(136, t, 1620, 1200, 1580, 1234, 1400, 0, 0, 0, 0, 0, 0, 0, 0, 0)
            d.msg(140, t, k * 0.0025, 0.1 * math.sin(k / 10), 2.0, 0, 0, 0, 0, 0, 0)
        if k % 40 == 0:
            d.msg(133, t, 0, 12.0, 500.0, 95000.0 + k, 25.5, 0, 0, 0, 0, 1)
            d.msg(134, t, 0, 21.9, 240.0, 20.0, 0, 0, 1, 1, 1, 0, 0)
            d.msg(135, t, 0, 200, -50, 400, 0, 0, 0, 0, 0, 0, 1, 0)
            d.msg(137, t, 0, 10.5, 0, -3.25, 0, 350.0, 0, 0, 0)
            d.msg(138, t, 47.3977419, 8.5455938, 488.5, 12.0, 12.0)
            d.msg(131, t, 0, 3, 300000000 + k, 2300, 12, 0.8, 47.3977419, 8.5455938, 488.5, 20.0, 30.0, -1.5, 0, 1)
            d.msg(132, t, 0, 1.2, 1.5, 2.5, 0.3, 0, 1, t // 1000, 0, 0)
    return bytes(d.out)


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    (out / "plane.bin").write_bytes(plane())
    (out / "plane_garbage.bin").write_bytes(plane(garbage=True))


if __name__ == "__main__":
    main()
