#!/usr/bin/env python3
"""A long PX4 ULog for `tern import ulog`'s memory bound (issue 43: importers stream).

Writes OUT.ulg: IN's header and definitions, then IN's data section REPEATS times, each copy's
timestamps (every data message's top-level uint64 `timestamp`, which PX4 formats put first, and
every logged string's) shifted past the previous copy's end (by the span from the header's start timestamp to the last data
timestamp), so every topic's time keeps rising.
Subscriptions ('A') are written once. Reads and writes one message at a time (the ULog spec's
`uint16 size, uint8 type, payload`).

    python3 bench/make_long_ulog.py ../shared/reference/ulog_samples/sample.ulg /tmp/long.ulg 53
    /usr/bin/time -v build/bin/tern import ulog /tmp/long.ulg /tmp/long_log   # "Maximum resident set size"

sample.ulg holds 68 s: 53 copies are an hour (215 MB).
"""
import struct
import sys

DEFINITION_TYPES = b"BFIMPQ"


def messages(f):
    """(offset, type, payload) of every whole message after the 16-byte header."""
    offset = 16
    f.seek(16)
    while True:
        head = f.read(3)
        if len(head) < 3:
            return
        size, kind = struct.unpack("<HB", head)
        payload = f.read(size)
        if len(payload) < size:
            return
        yield offset, kind, payload
        offset += 3 + size


def timestamp_first(formats, name):
    fields = formats.get(name, [])
    return bool(fields) and fields[0] == "uint64_t timestamp"


def main():
    src, dst, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3])
    formats, shifted_ids = {}, set()
    last = 0
    with open(src, "rb") as f:
        header = f.read(16)
        start = struct.unpack_from("<Q", header, 8)[0]  # the log's start, us since boot
        data_start = None
        for offset, kind, payload in messages(f):
            if kind == ord("F"):
                name, _, rest = payload.decode().partition(":")
                formats[name] = [x for x in rest.split(";") if x]
            elif chr(kind).encode() not in DEFINITION_TYPES and data_start is None:
                data_start = offset
            if kind == ord("A"):
                if timestamp_first(formats, payload[3:].decode()):
                    shifted_ids.add(struct.unpack_from("<H", payload, 1)[0])
            elif kind == ord("D") and struct.unpack_from("<H", payload, 0)[0] in shifted_ids:
                last = max(last, struct.unpack_from("<Q", payload, 2)[0])
        period = last - start + 4000  # us: one copy's span from the log's start, and a 4 ms gap
        with open(dst, "wb") as out:
            out.write(header)
            f.seek(16)
            out.write(f.read(data_start - 16))
            for copy in range(repeats):
                shift = copy * period
                for offset, kind, payload in messages(f):
                    if offset < data_start or (copy and kind == ord("A")):
                        continue
                    if kind == ord("D") and struct.unpack_from("<H", payload, 0)[0] in shifted_ids:
                        t = struct.unpack_from("<Q", payload, 2)[0]
                        payload = payload[:2] + struct.pack("<Q", t + shift if t else 0) + payload[10:]
                    elif kind == ord("L"):
                        t = struct.unpack_from("<Q", payload, 1)[0]
                        payload = payload[:1] + struct.pack("<Q", t + shift) + payload[9:]
                    out.write(struct.pack("<HB", len(payload), kind) + payload)
    print(f"{dst}: {repeats} copies of {src}'s data section, {repeats * period / 1e6:.0f} s")


if __name__ == "__main__":
    main()
