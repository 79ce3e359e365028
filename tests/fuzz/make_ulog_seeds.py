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
"""
import struct
import sys


def messages(data):
    pos = 16
    while pos + 3 <= len(data):
        size, kind = struct.unpack_from("<HB", data, pos)
        yield chr(kind), data[pos:pos + 3 + size], data[pos + 3:pos + 3 + size]
        pos += 3 + size


def main():
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
