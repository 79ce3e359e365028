#!/usr/bin/env python3
"""The hostile inputs of test_hostile.sh, generated small into WORK (nothing large is committed).

usage: make_inputs.py REPO WORK

WORK/logs/<case>/   sensor logs (docs/sensor-log.md): `good` (11 s of a still aircraft at 400 Hz),
                    `code` (good + a config.yaml setting plugin_path: [.]), `jump` (IMU t and stamp
                    jumping by 1e9 s = 1e18 ns from row 4000), `no_gyro_z`, `empty_imu`, `zero_imu`
                    (imu.csv a symlink to /dev/zero)
WORK/configs/       mission configs: the default mission made absolute, each with one hostile part
                    (fleet_dds_key.yaml: configs/missions/crossing.yaml with a hostile dds key;
                    dup_key.yaml: the default mission with `duration:` given twice)
WORK/dir/           an empty directory, given where a file is expected
WORK/alfa.tar.gz    an ALFA archive whose raw-IMU member is a symlink
WORK/sparse.tar.gz  an ALFA archive whose raw-IMU member is a GNU sparse file declaring 8 GiB (13 bytes
                    of data, then a hole): more than the 4 GiB an archive may unpack to
WORK/mtree.tar      an mtree listing naming /etc/passwd as a member's contents (mtree(5) contents=)
WORK/dot.tar        a tar whose regular member is named '.'
WORK/chunk.mcap     an MCAP file whose chunk declares 2^62 bytes uncompressed
WORK/bad_crc.mcap   an MCAP file whose chunk's CRC-32 is not its records'
WORK/plugins/       a libtern_estimator_ekf.so that is no ELF file (a text file)
"""
import io
import os
import struct
import sys
import tarfile
import zlib

import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fuzz"))
from seed_files import standard_gravity  # noqa: E402 (the shared reader of tern/math.hpp)

REPO, WORK = sys.argv[1], sys.argv[2]
MISSIONS = os.path.join(REPO, "configs", "missions")
IMU_RATE = 400  # Hz
JUMP_ROW = 4000  # the first IMU row (0-based) after the jump
JUMP_NS = 10**18


def table(path, columns, rows):
    with open(path, "w") as f:
        f.write(",".join(["t [s]"] + columns) + "\n")
        for t_ns, values in rows:
            f.write(f"{t_ns // 10**9}.{t_ns % 10**9:09d},{t_ns}," + ",".join(values) + "\n")


def imu_rows(n, jump_at=None):
    at_rest = ["0", "0", "-" + standard_gravity(), "0", "0", "0"]  # level and still: the accelerometer reads -g on z
    for k in range(n):
        t = k * (10**9 // IMU_RATE) + (JUMP_NS if jump_at is not None and k >= jump_at else 0)
        yield t, at_rest


IMU_COLUMNS = ["stamp", "accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"]


def sensor_log(name, imu=IMU_COLUMNS, imu_rows_=None):
    d = os.path.join(WORK, "logs", name)
    os.makedirs(os.path.join(d, "topics"))
    rows = list(imu_rows(4400) if imu_rows_ is None else imu_rows_)
    if imu != IMU_COLUMNS:  # drop the missing columns' values
        keep = [IMU_COLUMNS.index(c) - 1 for c in imu[1:]]
        rows = [(t, [v[i] for i in keep]) for t, v in rows]
    table(os.path.join(d, "topics", "imu.csv"), imu, rows)
    fix = ["0", "3", "12", "47.397", "8.545", "488", "0", "0", "0", "0.5", "0.8", "0.2"]
    table(os.path.join(d, "topics", "gnss.csv"),
          ["stamp", "time_of_validity", "fix_type", "num_sats", "lat", "lon", "alt", "vel_n", "vel_e", "vel_d", "h_acc", "v_acc", "s_acc"],
          [(k * 10**8, fix) for k in range(110)])
    table(os.path.join(d, "topics", "actuators.csv"), ["stamp", "delta_a", "delta_e", "delta_r", "delta_t"],
          [(k * 2 * 10**7, ["0", "0", "0", "0"]) for k in range(550)])
    return d


def sensor_logs():
    sensor_log("good")
    code = sensor_log("code")
    with open(os.path.join(REPO, "configs", "replay", "estimator.yaml")) as f:
        config = yaml.safe_load(f)
    config["plugin_path"] = ["."]  # the log's own directory, where its libtern_estimator_ekf.so lies
    with open(os.path.join(code, "config.yaml"), "w") as f:
        yaml.safe_dump(config, f)
    sensor_log("jump", imu_rows_=imu_rows(4400, JUMP_ROW))
    sensor_log("no_gyro_z", imu=[c for c in IMU_COLUMNS if c != "gyro_z"])
    sensor_log("gyro_x_twice", imu=IMU_COLUMNS + ["gyro_x"])  # which of the two is the field? (found by fuzz_csv_table)
    sensor_log("empty_imu", imu_rows_=[])
    utf16 = os.path.join(sensor_log("utf16_imu"), "topics", "imu.csv")  # as a Windows tool may save it
    with open(utf16, encoding="utf-8") as f:
        text = f.read()
    with open(utf16, "w", encoding="utf-16") as f:
        f.write(text)
    wide = os.path.join(sensor_log("wide_row"), "topics", "imu.csv")  # one row with three values too many
    with open(wide) as f:
        rows = f.read().split("\n")
    rows[4] += ",1,2,3"
    with open(wide, "w") as f:
        f.write("\n".join(rows))
    # a barometer in hPa (a median of 850 "Pa"), NaN rows among it: refused naming the unit, not
    # played as out of range with one warning (core/apps/replay/sensor_units.hpp)
    hpa = sensor_log("baro_hpa")
    table(os.path.join(hpa, "topics", "baro.csv"), ["stamp", "pressure"],
          [(k * 10**7, ["nan" if k % 7 == 0 else "850.0"]) for k in range(1100)])
    # IMU stamps in microseconds beside t in seconds (table_limits.hpp check_stamp_at_t)
    us = os.path.join(sensor_log("stamp_us"), "topics", "imu.csv")
    with open(us) as f:
        lines = f.read().split("\n")
    for i in range(1, len(lines)):
        if lines[i]:
            cells = lines[i].split(",")
            cells[1] = str(int(cells[1]) // 1000)
            lines[i] = ",".join(cells)
    with open(us, "w") as f:
        f.write("\n".join(lines))
    # the IMU's table separated by semicolons (a spreadsheet's CSV in a locale with decimal commas)
    semi = os.path.join(sensor_log("semicolons"), "topics", "imu.csv")
    with open(semi) as f:
        text = f.read()
    with open(semi, "w") as f:
        f.write(text.replace(",", ";"))
    # no commands table, and a sensor_log.yaml whose notes say why in a line with a terminal escape,
    # beside a note that is a map and one naming nothing: sysid's error names the import's line, one
    # line, no control character (sysid/import_notes.hpp)
    noted = sensor_log("no_actuators_noted")
    os.remove(os.path.join(noted, "topics", "actuators.csv"))
    with open(os.path.join(noted, "sensor_log.yaml"), "w") as f:
        f.write('tern_sensor_log: 1\nnotes:\n'
                '  - "import warning: log.bin: no actuators.csv written without --max-deflection A E R\\e[2J\\nsecond line"\n'
                '  - {import warning: "a map"}\n'
                '  - "import warning: about the barometer"\n')
    zero = sensor_log("zero_imu")
    os.remove(os.path.join(zero, "topics", "imu.csv"))
    os.symlink("/dev/zero", os.path.join(zero, "topics", "imu.csv"))


def default_config():
    """configs/missions/default.yaml with every path in it made absolute."""
    with open(os.path.join(MISSIONS, "default.yaml")) as f:
        c = yaml.safe_load(f)
    c["aircraft"] = os.path.normpath(os.path.join(MISSIONS, c["aircraft"]))
    for p in c["plugins"]:
        if "param_file" in p:
            p["param_file"] = os.path.normpath(os.path.join(MISSIONS, p["param_file"]))
    c["mission"]["file"] = os.path.normpath(os.path.join(MISSIONS, c["mission"]["file"]))
    return c


def write_config(name, edit):
    c = default_config()
    edit(c)
    with open(os.path.join(WORK, "configs", name + ".yaml"), "w") as f:
        yaml.safe_dump(c, f, width=10**9)


def configs():
    os.makedirs(os.path.join(WORK, "configs"))
    os.makedirs(os.path.join(WORK, "dir"))
    zero = os.path.join(WORK, "zero_waypoints.yaml")
    os.symlink("/dev/zero", zero)
    write_config("zero_waypoints", lambda c: c["mission"].update(file=zero))
    write_config("aircraft_dir", lambda c: c.update(aircraft=os.path.join(WORK, "dir")))
    write_config("param_dir", lambda c: c["plugins"][-1].update(param_file=os.path.join(WORK, "dir")))
    with open(default_config()["aircraft"]) as f:
        aircraft = yaml.safe_load(f)
    i = aircraft["inertia"]
    i["Jz"] = round(i["Jx"] + i["Jy"] + 0.1, 6)  # Jz > Jx + Jy: no rigid body
    bad = os.path.join(WORK, "bad_inertia.yaml")
    with open(bad, "w") as f:
        yaml.safe_dump(aircraft, f)
    write_config("bad_inertia", lambda c: c.update(aircraft=bad))
    write_config("escape", lambda c: c.update(name="\x1b[31mred\x07"))
    write_config("nan_duration", lambda c: c.update(duration=float("nan")))
    write_config("inf_rate", lambda c: c.update(base_rate=float("inf")))
    write_config("list_duration", lambda c: c.update(duration=[1, 2]))
    self_param = os.path.join(WORK, "configs", "self_param.yaml")  # an instance's parameter file: the config itself
    write_config("self_param", lambda c: c["plugins"][-1].update(param_file=self_param))
    os.makedirs(os.path.join(WORK, "plugins"))
    with open(os.path.join(WORK, "plugins", "libtern_estimator_ekf.so"), "w") as f:
        f.write("not a library\n")
    write_config("not_elf_plugin", lambda c: c.update(plugin_path=[os.path.join(WORK, "plugins")]))
    write_config("long_name", lambda c: c["plugins"][0].update(plugin="a" * 100000))
    # a key given twice: the default mission's duration again at the end
    with open(os.path.join(WORK, "configs", "dup_key.yaml"), "w") as f:
        yaml.safe_dump(default_config(), f, width=10**9)
        f.write("duration: 5\n")
    # a fleet (configs/missions/crossing.yaml) whose dds map has a key that is a list
    with open(os.path.join(MISSIONS, "crossing.yaml")) as f:
        fleet = f.read()
    with open(os.path.join(WORK, "configs", "fleet_dds_key.yaml"), "w") as f:
        f.write("dds:\n  [1, 2]: 3\n" + fleet)
    # an alias bomb: 10^6 nodes once expanded, 60 lines as written
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
    for k in range(1, 6):
        lines.append(f"a{k}: &a{k} [" + ", ".join([f"*a{k - 1}"] * 10) + "]")
    with open(os.path.join(WORK, "configs", "alias_bomb.yaml"), "w") as f:
        f.write("\n".join(lines) + "\nname: bomb\nmission: *a5\n")
    with open(os.path.join(WORK, "configs", "deep.yaml"), "w") as f:  # 5000 nested sequences, one line
        f.write("name: deep\nmission: " + "[" * 5000 + "]" * 5000 + "\n")


def alfa_archive():
    """An ALFA sequence whose raw IMU is a symlink: the filtered IMU must not stand in for it."""
    with tarfile.open(os.path.join(WORK, "alfa.tar.gz"), "w:gz") as tar:
        link = tarfile.TarInfo("seq/carbonZ_2018-07-18-mavros-imu-data_raw.csv")
        link.type, link.linkname = tarfile.SYMTYPE, "/etc/passwd"
        tar.addfile(link)
        data = b"%time,field.header.stamp\n"
        filtered = tarfile.TarInfo("seq/carbonZ_2018-07-18-mavros-imu-data.csv")
        filtered.size = len(data)
        tar.addfile(filtered, io.BytesIO(data))


def sparse_archive():
    """A raw IMU stored as a GNU sparse 1.0 member (pax headers, its map in the data) of 8 GiB."""
    data = b"%time,field\n0"
    body = f"1\n0\n{len(data)}\n".encode().ljust(512, b"\0") + data
    member = tarfile.TarInfo("seq/GNUSparseFile.0/carbonZ_2018-07-18-mavros-imu-data_raw.csv")
    member.size = len(body)
    member.pax_headers = {"GNU.sparse.major": "1", "GNU.sparse.minor": "0", "GNU.sparse.realsize": str(8 << 30),
                          "GNU.sparse.name": "seq/carbonZ_2018-07-18-mavros-imu-data_raw.csv"}
    with tarfile.open(os.path.join(WORK, "sparse.tar.gz"), "w:gz", format=tarfile.PAX_FORMAT) as tar:
        tar.addfile(member, io.BytesIO(body))


def other_archives():
    """An mtree "archive" (a listing whose members' bytes come from this machine's files), and a
    tar whose regular member is named '.' (fuzz_archive's finding: it replaced the directory)."""
    with open(os.path.join(WORK, "mtree.tar"), "w") as f:
        f.write("#mtree\nseq/carbonZ_2018-07-18-mavros-imu-data_raw.csv type=file contents=/etc/passwd\n")
    dot = tarfile.TarInfo(".")
    dot.size = 2
    with tarfile.open(os.path.join(WORK, "dot.tar"), "w") as tar:
        tar.addfile(dot, io.BytesIO(b"x\n"))


def mcap_chunk():
    """A valid MCAP header, then a chunk declaring 2^62 bytes uncompressed (https://mcap.dev/spec)."""
    def record(op, content):
        return struct.pack("<BQ", op, len(content)) + content
    magic = b"\x89MCAP0\r\n"
    header = struct.pack("<I", 0) + struct.pack("<I", 0)  # profile, library: empty strings
    chunk = struct.pack("<QQQI", 0, 0, 2**62, 0) + struct.pack("<I", 0) + struct.pack("<Q", 0)  # no compression, no records
    data_end = struct.pack("<I", 0)
    with open(os.path.join(WORK, "chunk.mcap"), "wb") as f:
        f.write(magic + record(0x01, header) + record(0x06, chunk) + record(0x0F, data_end))
        f.write(record(0x02, struct.pack("<QQI", 0, 0, 0)) + magic)


def mcap_bad_crc():
    """A chunk holding one Schema record whose declared CRC-32 is not that of its records."""
    def record(op, content):
        return struct.pack("<BQ", op, len(content)) + content
    def text(s):
        return struct.pack("<I", len(s)) + s
    magic = b"\x89MCAP0\r\n"
    schema = record(0x03, struct.pack("<H", 1) + text(b"tern/Imu") + text(b"jsonschema") + struct.pack("<I", 2) + b"{}")
    crc = (zlib.crc32(schema) ^ 0xFFFF) or 1  # wrong, and not 0 (0: "not computed")
    chunk = struct.pack("<QQQI", 0, 0, len(schema), crc) + text(b"") + struct.pack("<Q", len(schema)) + schema
    with open(os.path.join(WORK, "bad_crc.mcap"), "wb") as f:
        f.write(magic + record(0x01, text(b"") + text(b"")) + record(0x06, chunk) + record(0x0F, struct.pack("<I", 0)))
        f.write(record(0x02, struct.pack("<QQI", 0, 0, 0)) + magic)


sensor_logs()
configs()
alfa_archive()
sparse_archive()
other_archives()
mcap_chunk()
mcap_bad_crc()
