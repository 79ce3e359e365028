#!/usr/bin/env python3
"""Writes the seeds of fuzz_mcap_recovery (and fuzz_mcap_reader): small MCAP files laid out as tern's
flight log writes them (core/formats/mcap/mcap_writer.cpp, https://mcap.dev/spec): the magic, a
header (profile ros2), a schema and two channels (tern_msgs/msg/Imu in CDR, a topic without a
schema), chunks of messages with their message indexes, a metadata and an attachment record, the
data end, the summary and the footer; then the same file cut short where a killed flight leaves
it (inside the second chunk, before the data end), one with its chunk uncompressed and one with
messages outside any chunk. Chunks are compressed with the zstd command-line tool.

  make_mcap_seeds.py OUT_DIR
"""
import os
import struct
import subprocess
import sys
import zlib

from seed_files import standard_gravity, write_seeds

MAGIC = b"\x89MCAP0\r\n"
OP = {"header": 0x01, "footer": 0x02, "schema": 0x03, "channel": 0x04, "message": 0x05, "chunk": 0x06, "message_index": 0x07,
      "chunk_index": 0x08, "attachment": 0x09, "statistics": 0x0B, "metadata": 0x0C, "data_end": 0x0F, "summary_offset": 0x0E}

IMU_SCHEMA = b"int64 stamp  # ns\nfloat64 accel_x  # m/s^2\nfloat64 accel_y  # m/s^2\nfloat64 accel_z  # m/s^2\n" \
             b"float64 gyro_x  # rad/s\nfloat64 gyro_y  # rad/s\nfloat64 gyro_z  # rad/s\n"


def record(op, content):
    return struct.pack("<BQ", OP[op], len(content)) + content


def s(text):
    b = text.encode() if isinstance(text, str) else text
    return struct.pack("<I", len(b)) + b


def smap(pairs):
    body = b"".join(s(k) + s(v) for k, v in pairs)
    return struct.pack("<I", len(body)) + body


def imu_cdr(t_ns, k):
    # CDR little-endian header, then stamp and six doubles (aligned to 8 from the header's end)
    return b"\x00\x01\x00\x00" + struct.pack("<q6d", t_ns, 0.01 * k, -0.02, -float(standard_gravity()), 0.001 * k, 0.0, -0.003)


def message(channel, seq, t_ns, data):
    return record("message", struct.pack("<HIQQ", channel, seq, t_ns, t_ns) + data)


def zstd(data):
    return subprocess.run(["zstd", "-q", "-c", "-1"], input=data, stdout=subprocess.PIPE, check=True).stdout


def chunk(messages, compress=True):
    """A chunk record of `messages` [(channel, seq, t, data)] and its message index records."""
    records, index = b"", {}
    for ch, seq, t, data in messages:
        index.setdefault(ch, []).append((t, len(records)))
        records += message(ch, seq, t, data)
    packed = zstd(records) if compress else records
    times = [m[2] for m in messages]
    out = record("chunk", struct.pack("<QQQI", min(times), max(times), len(records), zlib.crc32(records)) +
                 s("zstd" if compress else "") + struct.pack("<Q", len(packed)) + packed)
    for ch, entries in sorted(index.items()):
        out += record("message_index", struct.pack("<HI", ch, 16 * len(entries)) + b"".join(struct.pack("<QQ", t, o) for t, o in entries))
    return out


def flight(compress=True, loose=False):
    head = MAGIC + record("header", s("ros2") + s("tern"))
    decl = record("schema", struct.pack("<H", 1) + s("tern_msgs/msg/Imu") + s("ros2msg") + s(IMU_SCHEMA))
    decl += record("channel", struct.pack("<HH", 1, 1) + s("imu") + s("cdr") + smap([("tern.csv_header", "t [s],stamp [ns],accel_x")]))
    decl += record("channel", struct.pack("<HH", 2, 0) + s("events") + s("json") + smap([]))
    first = [(1, k, 2_500_000 * k, imu_cdr(2_500_000 * k, k)) for k in range(4)] + [(2, 0, 5_000_000, b'{"phase":"climb"}')]
    second = [(1, k, 2_500_000 * k, imu_cdr(2_500_000 * k, k)) for k in range(4, 7)]
    if loose:
        body = b"".join(message(*m) for m in first)
    else:
        body = chunk(first, compress)
    body += record("metadata", s("flight") + smap([("mission", "default"), ("seed", "1")]))
    body += record("attachment", struct.pack("<QQ", 10_000_000, 0) + s("config.yaml") + s("application/yaml") +
                   struct.pack("<Q", 14) + b"name: default\n" + struct.pack("<I", 0))
    cut_inside = len(head + decl + body) + 40  # inside the second chunk's record
    body += chunk(second, compress)
    cut_before_end = len(head + decl + body)
    data_end = record("data_end", struct.pack("<I", 0))
    summary = decl + record("statistics", struct.pack("<QHIIIIQQ", 8, 1, 2, 1, 1, 2, 0, 15_000_000) + struct.pack("<I", 0))
    summary_start = len(head + decl + body + data_end)
    tail = summary + record("summary_offset", struct.pack("<BQQ", OP["schema"], summary_start, len(summary)))
    footer = record("footer", struct.pack("<QQI", summary_start, summary_start + len(summary), 0))
    whole = head + decl + body + data_end + tail + footer + MAGIC
    return whole, cut_inside, cut_before_end


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    whole, cut_inside, cut_before_end = flight()
    seeds = {
        "flight.mcap": whole,
        "flight_cut_in_chunk.mcap": whole[:cut_inside],
        "flight_cut_before_data_end.mcap": whole[:cut_before_end],
        "flight_uncompressed.mcap": flight(compress=False)[0],
        "flight_loose_messages.mcap": flight(loose=True)[0],
    }
    write_seeds(out, seeds)


if __name__ == "__main__":
    main()
