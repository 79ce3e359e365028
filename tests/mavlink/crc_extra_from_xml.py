#!/usr/bin/env python3
"""CRC_EXTRA and wire layout of MAVLink messages, computed from a dialect's XML as the spec defines.

Usage: crc_extra_from_xml.py COMMON_XML [NAME ...]
       crc_extra_from_xml.py COMMON_XML --entries ENTRY ...   (the values of enum entries)
  COMMON_XML: message_definitions/v1.0/common.xml of github.com/mavlink/mavlink; its <include>s
  (standard.xml, minimal.xml: HEARTBEAT, GLOBAL_POSITION_INT) are read from the same folder.
Prints, per message: id, name, CRC_EXTRA, the base payload length, and the fields in wire order
(offset, type, name, array length), extension fields last in XML order.

The algorithm (https://mavlink.io/en/guide/serialization.html#crc_extra): an X.25 CRC (CRC-16/MCRF4XX)
over "MESSAGE_NAME " then, for each non-extension field in wire order (sorted by the size of its
base type, largest first, stable), "type " and "name " (uint8_t_mavlink_version counts as uint8_t),
then the array length as one byte for an array; CRC_EXTRA = (crc & 0xFF) ^ (crc >> 8).
tern's codec (core/apps/mavlink/mavlink_messages.cpp) carries the values; its unit test checks them
against this computation's output for common.xml (tests/mavlink/crc_extra_common.txt).
"""
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

SIZES = {"char": 1, "int8_t": 1, "uint8_t": 1, "int16_t": 2, "uint16_t": 2, "int32_t": 4, "uint32_t": 4,
         "float": 4, "int64_t": 8, "uint64_t": 8, "double": 8}


def x25(data: bytes, crc: int = 0xFFFF) -> int:
    for b in data:
        t = b ^ (crc & 0xFF)
        t = (t ^ (t << 4)) & 0xFF
        crc = ((crc >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4)) & 0xFFFF
    return crc


def fields_of(msg):
    base, ext, in_ext = [], [], False
    for child in msg:
        if child.tag == "extensions":
            in_ext = True
        elif child.tag == "field":
            t = child.get("type").replace("uint8_t_mavlink_version", "uint8_t")
            m = re.match(r"(\w+)\[(\d+)\]", t)
            typ, n = (m.group(1), int(m.group(2))) if m else (t, 0)
            (ext if in_ext else base).append((typ, child.get("name"), n))
    return sorted(base, key=lambda f: -SIZES[f[0]]), ext


def crc_extra(name, base):
    crc = x25((name + " ").encode())
    for typ, fname, n in base:
        crc = x25((typ + " " + fname + " ").encode(), crc)
        if n:
            crc = x25(bytes([n]), crc)
    return (crc & 0xFF) ^ (crc >> 8)


def messages(path: Path, seen: set) -> list:
    """The <message>s of a dialect file and of the files it includes, each file once."""
    if path.resolve() in seen:
        return []
    seen.add(path.resolve())
    root = ET.parse(path).getroot()
    out = []
    for inc in root.iter("include"):
        out += messages(path.parent / inc.text.strip(), seen)
    return out + list(root.iter("message"))


def entries(path: Path, wanted: set) -> int:
    """Prints 'ENTRY value' for each enum entry named in `wanted`, in the order asked."""
    found = {}
    for xml in [path, path.parent / "standard.xml", path.parent / "minimal.xml"]:
        for e in ET.parse(xml).getroot().iter("entry"):
            if e.get("name") in wanted:
                found[e.get("name")] = e.get("value")
    for name in sorted(wanted):
        print(f"{name} {found.get(name, 'MISSING')}")
    return 0 if len(found) == len(wanted) else 1


def main() -> int:
    if len(sys.argv) > 2 and sys.argv[2] == "--entries":
        return entries(Path(sys.argv[1]), set(sys.argv[3:]))
    wanted = set(sys.argv[2:])
    for msg in sorted(messages(Path(sys.argv[1]), set()), key=lambda m: int(m.get("id"))):
        name = msg.get("name")
        if wanted and name not in wanted:
            continue
        base, ext = fields_of(msg)
        off, layout = 0, []
        for typ, fname, n in base + ext:
            layout.append(f"{off}:{typ} {fname}" + (f"[{n}]" if n else ""))
            off += SIZES[typ] * max(n, 1)
        base_len = sum(SIZES[t] * max(n, 1) for t, _, n in base)
        print(f"{msg.get('id')} {name} {crc_extra(name, base)} {base_len} | " + ", ".join(layout))
    return 0


if __name__ == "__main__":
    sys.exit(main())
