#!/usr/bin/env python3
"""Generates tern's MAVLink 1.0 message structs for the ROSflight dialect from rosflight.xml.

Usage: generate.py DIALECT.xml OUTPUT.hpp MESSAGE_NAME...

For every message of the dialect the output lists its id, payload length and CRC_EXTRA (so that
the parser can check the CRC of any dialect frame); for each MESSAGE_NAME it also emits a struct
with the fields in definition order and pack()/unpack() in wire order.

CRC_EXTRA follows the MAVLink generator's rule: X.25 CRC over "NAME " and, for each field in
wire order, "type " and "name " (plus one byte with the array length for arrays), folded to
one byte as (crc & 0xFF) ^ (crc >> 8). Wire order sorts the fields by the size of their base
type, largest first, keeping definition order between equal sizes (a stable sort). The special
type uint8_t_mavlink_version is a uint8_t on the wire and in the CRC.

Python 3 standard library only (xml.etree).
"""
import sys
import xml.etree.ElementTree as ET

SIZES = {
    "char": 1, "uint8_t": 1, "int8_t": 1, "uint16_t": 2, "int16_t": 2, "uint32_t": 4,
    "int32_t": 4, "uint64_t": 8, "int64_t": 8, "float": 4, "double": 8,
}
CPP = {
    "char": "char", "uint8_t": "std::uint8_t", "int8_t": "std::int8_t", "uint16_t": "std::uint16_t",
    "int16_t": "std::int16_t", "uint32_t": "std::uint32_t", "int32_t": "std::int32_t",
    "uint64_t": "std::uint64_t", "int64_t": "std::int64_t", "float": "float", "double": "double",
}


def x25(data, crc=0xFFFF):
    for b in data:
        tmp = b ^ (crc & 0xFF)
        tmp = (tmp ^ (tmp << 4)) & 0xFF
        crc = ((crc >> 8) ^ (tmp << 8) ^ (tmp << 3) ^ (tmp >> 4)) & 0xFFFF
    return crc


def read_dialect(path):
    """The root element of the dialect file; a malformed file or an <include> is one error line."""
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as e:
        raise SystemExit(f"{path}: cannot read the dialect: {e}")
    for inc in root.iter("include"):
        raise SystemExit(f"{path}: <include>{inc.text}</include> is not supported (one self-contained dialect file)")
    return root


class Field:
    def __init__(self, el):
        self.name = el.get("name")
        t = el.get("type")
        # MAVLink's magic type: a uint8_t on the wire, filled by the sender with MAVLINK_VERSION
        self.is_mavlink_version = t == "uint8_t_mavlink_version"
        if self.is_mavlink_version:
            t = "uint8_t"
        self.array = 0
        if "[" in t:
            t, n = t.split("[")
            self.array = int(n.rstrip("]"))
        if t not in SIZES:
            raise SystemExit(f"field {self.name}: unknown type {t}")
        self.type = t
        self.size = SIZES[t]
        self.wire = self.size * max(1, self.array)


def base_fields(el):
    """The fields of a message element up to <extensions/> (wire protocol 1.0 has no extensions:
    the MAVLink generator drops the fields after that marker)."""
    fields = []
    for child in el:
        if child.tag == "extensions":
            break
        if child.tag == "field":
            try:
                fields.append(Field(child))
            except SystemExit as e:
                raise SystemExit(f"message {el.get('name')}: {e}")
    return fields


class Message:
    def __init__(self, el):
        self.id = int(el.get("id"))
        self.name = el.get("name")
        self.fields = base_fields(el)
        self.ordered = sorted(self.fields, key=lambda f: f.size, reverse=True)  # stable
        self.length = sum(f.wire for f in self.fields)
        crc = x25((self.name + " ").encode())
        for f in self.ordered:
            crc = x25((f.type + " ").encode(), crc)
            crc = x25((f.name + " ").encode(), crc)
            if f.array:
                crc = x25(bytes([f.array]), crc)
        self.crc_extra = (crc & 0xFF) ^ (crc >> 8)


def camel(name):
    return "".join(p.capitalize() for p in name.lower().split("_"))


def struct_code(m):
    out = [f"/// {m.name} (id {m.id}): {m.length} bytes on the wire, CRC_EXTRA {m.crc_extra}.",
           f"struct {camel(m.name)} {{",
           f"  static constexpr std::uint8_t kId = {m.id};",
           f"  static constexpr std::uint8_t kCrcExtra = {m.crc_extra};",
           f"  static constexpr std::uint8_t kLength = {m.length};",
           f"  static constexpr const char* kName = \"{m.name}\";"]
    for f in m.fields:
        t = CPP[f.type]
        if f.array:
            out.append(f"  std::array<{t}, {f.array}> {f.name}{{}};")
        else:
            out.append(f"  {t} {f.name} = 0;")
    out.append("  /// Writes the payload (kLength bytes, wire order, little-endian) to p.")
    out.append("  void pack(std::uint8_t* p) const {")
    off = 0
    for f in m.ordered:
        if f.array:
            out.append(f"    detail::put_array(p + {off}, {f.name});")
        else:
            out.append(f"    detail::put(p + {off}, {f.name});")
        off += f.wire
    out.append("  }")
    out.append("  /// Reads a payload of kLength bytes.")
    out.append(f"  static {camel(m.name)} unpack(const std::uint8_t* p) {{")
    out.append(f"    {camel(m.name)} m;")
    off = 0
    for f in m.ordered:
        if f.array:
            out.append(f"    detail::get_array(p + {off}, m.{f.name});")
        else:
            out.append(f"    detail::get(p + {off}, m.{f.name});")
        off += f.wire
    out.append("    return m;")
    out.append("  }")
    out.append("};")
    return "\n".join(out)


def main():
    if len(sys.argv) < 3:
        raise SystemExit("usage: generate.py DIALECT.xml OUTPUT.hpp MESSAGE_NAME...")
    root = read_dialect(sys.argv[1])
    msgs = [Message(el) for el in root.iter("message")]
    by_name = {m.name: m for m in msgs}
    wanted = sys.argv[3:]
    for w in wanted:
        if w not in by_name:
            raise SystemExit(f"generate.py: {sys.argv[1]} has no message {w}")
    lines = [
        "// Generated by plugins/fcu_serial/mavlink/generate.py from rosflight.xml. Do not edit.",
        "#pragma once",
        "",
        "#include <array>",
        "#include <cstdint>",
        "",
        "#include \"tern_fcu_serial/wire.hpp\"",
        "",
        "namespace tern::fcu::mavlink {",
        "",
        "/// Every message of the dialect: id, payload length and CRC_EXTRA.",
        "struct MessageInfo { std::uint8_t id; std::uint8_t length; std::uint8_t crc_extra; const char* name; };",
        f"inline constexpr std::array<MessageInfo, {len(msgs)}> kDialect{{{{",
    ]
    for m in sorted(msgs, key=lambda m: m.id):
        lines.append(f"    {{{m.id}, {m.length}, {m.crc_extra}, \"{m.name}\"}},")
    lines.append("}};")
    lines.append("")
    for w in wanted:
        lines.append(struct_code(by_name[w]))
        lines.append("")
    lines.append("}  // namespace tern::fcu::mavlink")
    text = "\n".join(lines) + "\n"
    try:
        with open(sys.argv[2]) as f:
            if f.read() == text:
                return
    except OSError:
        pass
    with open(sys.argv[2], "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()
