#!/usr/bin/env python3
"""Generates tern's MAVLink message structs from a dialect's XML, for wire protocol 1.0 or 2.0.

Usage: generate.py [--wire 1|2] [--namespace NS] [--known all|named] DIALECT.xml OUTPUT.hpp MESSAGE_NAME...
  --wire 1 (default): the fields up to <extensions/> (MAVLink 1.0 has none); ids 0..255.
  --wire 2: the extension fields too, after the base fields in XML order; ids of 24 bits.
  --namespace: the C++ namespace of the output (default tern::mavlink).
  --known all (default): the table kDialect lists every message of the dialect; named: only the
    MESSAGE_NAMEs (a receiver then counts any other id as unknown).
The dialect's <include>s are read from its folder, each file once (common.xml includes
standard.xml, which includes minimal.xml).

For every message of the table the output lists its id, payload length (base plus extensions in
wire protocol 2.0), base length, CRC_EXTRA and where its target_system field is (a router's
target_system_ofs); for each MESSAGE_NAME it also emits a struct with
the fields in definition order and pack()/unpack() of the kLength payload bytes in wire order.
Framing and checksum are tern/mavlink/frame.hpp's (one implementation for both versions).

CRC_EXTRA follows the MAVLink generator's rule: X.25 CRC over "NAME " and, for each base field in
wire order, "type " and "name " (plus one byte with the array length for arrays), folded to one
byte as (crc & 0xFF) ^ (crc >> 8). Wire order sorts the base fields by the size of their type,
largest first, keeping definition order between equal sizes (a stable sort); extension fields
follow in definition order and are not part of CRC_EXTRA. The special type
uint8_t_mavlink_version is a uint8_t on the wire and in the CRC; its struct field defaults to the
dialect's <version> when the dialect states one (else 0).

Python 3 standard library only (xml.etree).
"""
import os
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


def parse(path):
    try:
        return ET.parse(path).getroot()
    except (OSError, ET.ParseError) as e:
        raise SystemExit(f"{path}: cannot read the dialect: {e}")


def read_dialect(path):
    """The root element of a self-contained dialect file; a malformed file or an <include> is one
    error line (the C API of generate_c.py takes one file)."""
    root = parse(path)
    for inc in root.iter("include"):
        raise SystemExit(f"{path}: <include>{inc.text}</include> is not supported (one self-contained dialect file)")
    return root


def read_messages(path, seen=None):
    """The <message> elements of a dialect and of the files it includes (from its folder, each
    file once), in file order: the included files' first."""
    seen = set() if seen is None else seen
    real = os.path.realpath(path)
    if real in seen:
        return []
    seen.add(real)
    root = parse(path)
    out = []
    for inc in root.findall("include"):
        out += read_messages(os.path.join(os.path.dirname(path), (inc.text or "").strip()), seen)
    return out + list(root.iter("message"))


def dialect_version(path):
    """The <version> the dialect file states, or None."""
    el = parse(path).find("version")
    if el is None:
        return None
    try:
        return int(el.text)
    except (TypeError, ValueError):
        raise SystemExit(f"{path}: <version>{el.text}</version> is not an integer")


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


def split_fields(el):
    """The fields of a message element before and after <extensions/>."""
    base, ext = [], []
    into = base
    for child in el:
        if child.tag == "extensions":
            into = ext
        elif child.tag == "field":
            try:
                into.append(Field(child))
            except SystemExit as e:
                raise SystemExit(f"message {el.get('name')}: {e}")
    return base, ext


def base_fields(el):
    """The fields of a message element up to <extensions/> (wire protocol 1.0 has no extensions:
    the MAVLink generator drops the fields after that marker)."""
    return split_fields(el)[0]


class Message:
    """A message as wire protocol 1.0 (wire=1: base fields only) or 2.0 (wire=2: the extension
    fields after them) lays it out."""

    def __init__(self, el, wire=1):
        self.id = int(el.get("id"))
        self.name = el.get("name")
        self.fields, ext = split_fields(el)
        self.ordered = sorted(self.fields, key=lambda f: f.size, reverse=True)  # stable
        self.min_length = sum(f.wire for f in self.fields)
        crc = x25((self.name + " ").encode())
        for f in self.ordered:
            crc = x25((f.type + " ").encode(), crc)
            crc = x25((f.name + " ").encode(), crc)
            if f.array:
                crc = x25(bytes([f.array]), crc)
        self.crc_extra = (crc & 0xFF) ^ (crc >> 8)
        if wire == 2:
            self.fields += ext
            self.ordered += ext
        self.length = sum(f.wire for f in self.fields)
        self.target_system_offset = -1  # where target_system is in the payload (wire order), as MAVLink's target_system_ofs
        off = 0
        for f in self.ordered:
            if f.name == "target_system":
                self.target_system_offset = off
            off += f.wire


def camel(name):
    return "".join(p.capitalize() for p in name.lower().split("_"))


def field_code(f, version):
    t = CPP[f.type]
    if f.array:
        return f"  std::array<{t}, {f.array}> {f.name}{{}};"
    value = version if f.is_mavlink_version and version is not None else 0
    return f"  {t} {f.name} = {value};"


def pack_code(m):
    out = ["  /// Writes the payload (kLength bytes, wire order, little-endian) to p.",
           "  void pack(std::uint8_t* p) const {"]
    off = 0
    for f in m.ordered:
        put = "put_array" if f.array else "put"
        out.append(f"    ::tern::mavlink::detail::{put}(p + {off}, {f.name});")
        off += f.wire
    out += ["  }", "  /// Reads a payload of kLength bytes.", f"  static {camel(m.name)} unpack(const std::uint8_t* p) {{",
            f"    {camel(m.name)} m;"]
    off = 0
    for f in m.ordered:
        get = "get_array" if f.array else "get"
        out.append(f"    ::tern::mavlink::detail::{get}(p + {off}, m.{f.name});")
        off += f.wire
    return out + ["    return m;", "  }"]


def struct_code(m, wire, version):
    id_type = "std::uint8_t" if wire == 1 else "std::uint32_t"
    sizes = f"{m.length} bytes on the wire" if wire == 1 else f"{m.length} bytes with extensions, {m.min_length} without"
    out = [f"/// {m.name} (id {m.id}): {sizes}, CRC_EXTRA {m.crc_extra}.",
           f"struct {camel(m.name)} {{",
           f"  static constexpr {id_type} kId = {m.id};",
           f"  static constexpr std::uint8_t kCrcExtra = {m.crc_extra};",
           f"  static constexpr std::uint8_t kLength = {m.length};"]
    if wire == 2:
        out.append(f"  static constexpr std::uint8_t kMinLength = {m.min_length};")
    out.append(f"  static constexpr const char* kName = \"{m.name}\";")
    out += [field_code(f, version) for f in m.fields]
    return "\n".join(out + pack_code(m) + ["};"])


def check(m, wire, path):
    """One error line when a message does not fit the wire protocol's id or payload."""
    if wire == 1 and not 0 <= m.id <= 255:
        raise SystemExit(f"{path}: message {m.name}: id {m.id} does not fit MAVLink 1.0 (0..255)")
    if not 0 <= m.id < 1 << 24:
        raise SystemExit(f"{path}: message {m.name}: id {m.id} does not fit MAVLink 2.0's 24 bits")
    if m.length > 255:
        raise SystemExit(f"{path}: message {m.name}: payload of {m.length} bytes exceeds 255")


def table_code(msgs, wire):
    id_type = "std::uint8_t" if wire == 1 else "std::uint32_t"
    lines = [
        "/// Messages of the dialect: id, payload length (with extensions in MAVLink 2), base length, CRC_EXTRA, name, and the",
        "/// offset of the target_system field in the payload (-1: the message has none; routers send it to every system).",
        f"struct MessageInfo {{ {id_type} id; std::uint8_t length; std::uint8_t min_length; std::uint8_t crc_extra; "
        "const char* name; std::int16_t target_system_offset; };",
        f"inline constexpr std::array<MessageInfo, {len(msgs)}> kDialect{{{{",
    ]
    for m in sorted(msgs, key=lambda m: m.id):
        lines.append(f"    {{{m.id}, {m.length}, {m.min_length}, {m.crc_extra}, \"{m.name}\", {m.target_system_offset}}},")
    return lines + ["}};", ""]


def options(argv):
    opts = {"--wire": "1", "--namespace": "tern::mavlink", "--known": "all"}
    rest = []
    i = 1
    while i < len(argv):
        if argv[i] in opts and i + 1 < len(argv):
            opts[argv[i]] = argv[i + 1]
            i += 2
        else:
            rest.append(argv[i])
            i += 1
    if len(rest) < 2 or opts["--wire"] not in ("1", "2") or opts["--known"] not in ("all", "named"):
        raise SystemExit("usage: generate.py [--wire 1|2] [--namespace NS] [--known all|named] DIALECT.xml OUTPUT.hpp MESSAGE_NAME...")
    return int(opts["--wire"]), opts["--namespace"], opts["--known"], rest[0], rest[1], rest[2:]


def header_text(path, wire, namespace, known, wanted):
    msgs = [Message(el, wire) for el in read_messages(path)]
    by_name = {}
    for m in msgs:
        check(m, wire, path)
        if m.name in by_name:
            raise SystemExit(f"{path}: message {m.name} is defined twice")
        by_name[m.name] = m
    for w in wanted:
        if w not in by_name:
            raise SystemExit(f"generate.py: {path} has no message {w}")
    table = msgs if known == "all" else [by_name[w] for w in wanted]
    lines = [f"// Generated by sdk/mavlink/generate.py (MAVLink {wire}.0) from {os.path.basename(path)}. Do not edit.",
             "#pragma once", "", "#include <array>", "#include <cstdint>", "", "#include \"tern/mavlink/fields.hpp\"", "",
             f"namespace {namespace} {{", ""]
    lines += table_code(table, wire)
    version = dialect_version(path)
    for w in wanted:
        lines += [struct_code(by_name[w], wire, version), ""]
    return "\n".join(lines + [f"}}  // namespace {namespace}"]) + "\n"


def write_if_changed(path, text):
    """Writes text to path unless it already holds it (so that nothing rebuilds for nothing)."""
    try:
        with open(path) as f:
            if f.read() == text:
                return
    except OSError:
        pass
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def main(argv):
    wire, namespace, known, path, output, wanted = options(argv)
    write_if_changed(output, header_text(path, wire, namespace, known, wanted))


if __name__ == "__main__":
    main(sys.argv)
