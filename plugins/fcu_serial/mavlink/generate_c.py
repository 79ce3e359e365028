#!/usr/bin/env python3
"""Generates the MAVLink 1.0 C API of a dialect (the API of the MAVLink project's C generator,
mavgen --lang=C --wire-protocol=1.0) as one self-contained header, for C++ code written against
that library (the ROSflight firmware's mavlink_adapter.cpp includes "rosflight/mavlink.h").

Usage: generate_c.py DIALECT.xml OUT_DIR   (writes OUT_DIR/<dialect>/mavlink.h)

The header holds, for every enum of the dialect, `typedef enum NAME {ENTRY=value, ...,
NAME_ENUM_END=max+1} NAME;` and, for every message, MAVLINK_MSG_ID_<NAME> (and _LEN, _CRC),
the packed struct mavlink_<name>_t with the fields in wire order, and mavlink_msg_<name>_pack,
_pack_chan, _encode, _encode_chan, _decode and _get_<field>; then the framing (checksum, the
per-channel sequence counter, mavlink_msg_to_send_buffer) and the parser (mavlink_parse_char),
from c_api_core.h.in. The XML parsing, wire order and CRC_EXTRA are sdk/mavlink/generate.py's.

Behaviour that differs from mavgen's output (on purpose): a char[N] argument of _pack is copied
up to its terminating NUL and zero-filled (mavgen copies N bytes, reading past a short string);
the parser drops frames whose message id the dialect lacks or whose length is not the message's
(mavgen only does so with MAVLINK_CHECK_MESSAGE_LENGTH). The header needs a little-endian host.

Python 3 standard library only.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "sdk", "mavlink"))
import generate  # noqa: E402  (sdk/mavlink/generate.py: the one MAVLink generator)

CORE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "c_api_core.h.in")
C_TYPES = {t: t for t in generate.SIZES}  # char, uint8_t ... double: the same names in C


class Enum:
    """An enum of the dialect: entries sorted by value (mavgen's rule: an entry without a value
    takes the highest value so far + 1, counting from 0; then NAME_ENUM_END = the largest + 1)."""

    def __init__(self, el, path):
        self.name = el.get("name")
        entries, highest = [], 0
        for e in el.findall("entry"):
            value = self.entry_value(e, highest, path)
            highest = max(highest, value)
            entries.append((e.get("name"), value))
        if not entries:
            raise SystemExit(f"{path}: enum {self.name} has no entry")
        self.entries = sorted(entries, key=lambda kv: kv[1])  # stable, as mavgen's sort
        self.end = self.entries[-1][1] + 1

    def entry_value(self, e, highest, path):
        text = e.get("value")
        if text is None:
            return highest + 1
        try:
            return int(text, 0)
        except ValueError:
            raise SystemExit(f"{path}: enum {self.name}, entry {e.get('name')}: value {text!r} is not an integer")


def read_enums(root, path):
    enums = [Enum(el, path) for el in root.iter("enum")]
    seen = set()
    for en in enums:
        if en.name in seen:
            raise SystemExit(f"{path}: enum {en.name} is defined twice")
        seen.add(en.name)
    return enums


def read_messages(root, path):
    try:
        msgs = [generate.Message(el) for el in root.iter("message")]
    except SystemExit as e:
        raise SystemExit(f"{path}: {e}")
    ids = {}
    for m in msgs:
        generate.check(m, 1, path)
        if m.id in ids:
            raise SystemExit(f"{path}: message {m.name}: id {m.id} is already {ids[m.id]}")
        ids[m.id] = m.name
    return msgs


def dialect_version(root, path):
    """The dialect's <version> (HEARTBEAT's mavlink_version), 2 when absent as in mavgen."""
    el = root.find("version")
    if el is None:
        return 2
    try:
        return int(el.text)
    except (TypeError, ValueError):
        raise SystemExit(f"{path}: <version>{el.text}</version> is not an integer")


def enum_code(en):
    lines = [f"#ifndef HAVE_ENUM_{en.name}", f"#define HAVE_ENUM_{en.name}", f"typedef enum {en.name} {{"]
    lines += [f"  {name} = {value}," for name, value in en.entries]
    lines += [f"  {en.name}_ENUM_END = {en.end},", f"}} {en.name};", "#endif", ""]
    return lines


def wire_offsets(m):
    """(field, offset in the payload) in wire order."""
    out, off = [], 0
    for f in m.ordered:
        out.append((f, off))
        off += f.wire
    return out


def struct_code(m):
    lower = m.name.lower()
    lines = [f"#define MAVLINK_MSG_ID_{m.name} {m.id}", "#pragma pack(push, 1)", f"typedef struct __mavlink_{lower}_t {{"]
    for f in m.ordered:
        dim = f"[{f.array}]" if f.array else ""
        lines.append(f"  {C_TYPES[f.type]} {f.name}{dim};")
    lines += [f"}} mavlink_{lower}_t;", "#pragma pack(pop)"]
    for suffix, value in (("LEN", m.length), ("MIN_LEN", m.length), ("CRC", m.crc_extra)):
        lines.append(f"#define MAVLINK_MSG_ID_{m.name}_{suffix} {value}")
        lines.append(f"#define MAVLINK_MSG_ID_{m.id}_{suffix} {value}")
    lines += [f"#define MAVLINK_MSG_{m.name}_FIELD_{f.name.upper()}_LEN {f.array}" for f in m.fields if f.array]
    lines.append(f"static_assert(sizeof(mavlink_{lower}_t) == {m.length}, \"{m.name}: struct size is the payload length\");")
    for f, off in wire_offsets(m):
        lines.append(f"static_assert(offsetof(mavlink_{lower}_t, {f.name}) == {off}, \"{m.name}.{f.name}: wire offset\");")
    return lines


def param_decl(f):
    """The _pack argument of a field (definition order): char[N] as const char*, T[N] as const T*."""
    if f.array:
        return f"const {C_TYPES[f.type]}* {f.name}"
    return f"{C_TYPES[f.type]} {f.name}"


def args(m):
    return [f for f in m.fields if not f.is_mavlink_version]


def put_statement(f, off):
    if f.is_mavlink_version:
        return f"  {{ const uint8_t v = MAVLINK_VERSION; memcpy(p + {off}, &v, 1); }}"
    if f.array and f.type == "char":
        return f"  mavlink_copy_chars(p + {off}, {f.name}, {f.array});"
    if f.array:
        return f"  mavlink_copy_array(p + {off}, {f.name}, {f.wire});"
    return f"  memcpy(p + {off}, &{f.name}, {f.wire});"


def finalize(m, chan):
    return (f"  return mavlink_finalize_message_chan(msg, system_id, component_id, {chan}, MAVLINK_MSG_ID_{m.name}_MIN_LEN, "
            f"MAVLINK_MSG_ID_{m.name}_LEN, MAVLINK_MSG_ID_{m.name}_CRC);")


def pack_code(m):
    lower = m.name.lower()
    params = ", ".join(param_decl(f) for f in args(m))
    names = ", ".join(f.name for f in args(m))
    head = "uint8_t system_id, uint8_t component_id"
    lines = [f"/// Packs one {m.name} frame on channel chan; the fields in the order of the dialect. Returns the frame length.",
             f"static inline uint16_t mavlink_msg_{lower}_pack_chan({head}, uint8_t chan, mavlink_message_t* msg, {params}) {{",
             "  char* p = _MAV_PAYLOAD_NON_CONST(msg);"]
    lines += [put_statement(f, off) for f, off in wire_offsets(m)]
    lines += [f"  msg->msgid = MAVLINK_MSG_ID_{m.name};", finalize(m, "chan"), "}",
              f"/// mavlink_msg_{lower}_pack_chan on MAVLINK_COMM_0.",
              f"static inline uint16_t mavlink_msg_{lower}_pack({head}, mavlink_message_t* msg, {params}) {{",
              f"  return mavlink_msg_{lower}_pack_chan(system_id, component_id, MAVLINK_COMM_0, msg, {names});", "}"]
    return lines


def encode_code(m):
    lower = m.name.lower()
    head = f"uint8_t system_id, uint8_t component_id, uint8_t chan, mavlink_message_t* msg, const mavlink_{lower}_t* in"
    lines = [f"/// Packs the struct (as mavlink_msg_{lower}_pack_chan with its fields).",
             f"static inline uint16_t mavlink_msg_{lower}_encode_chan({head}) {{",
             "  char* p = _MAV_PAYLOAD_NON_CONST(msg);",
             f"  memcpy(p, in, MAVLINK_MSG_ID_{m.name}_LEN);"]
    lines += [put_statement(f, off) for f, off in wire_offsets(m) if f.is_mavlink_version]
    lines += [f"  msg->msgid = MAVLINK_MSG_ID_{m.name};", finalize(m, "chan"), "}",
              f"static inline uint16_t mavlink_msg_{lower}_encode(uint8_t system_id, uint8_t component_id, mavlink_message_t* msg, "
              f"const mavlink_{lower}_t* in) {{",
              f"  return mavlink_msg_{lower}_encode_chan(system_id, component_id, MAVLINK_COMM_0, msg, in);", "}"]
    return lines


def decode_code(m):
    lower, n = m.name.lower(), f"MAVLINK_MSG_ID_{m.name}_LEN"
    return [f"/// Unpacks the payload (msg->len bytes at most; the rest of the struct zeroed).",
            f"static inline void mavlink_msg_{lower}_decode(const mavlink_message_t* msg, mavlink_{lower}_t* out) {{",
            f"  const uint8_t len = msg->len < {n} ? msg->len : {n};",
            f"  memset(out, 0, {n});",
            "  memcpy(out, _MAV_PAYLOAD(msg), len);", "}"]


def getter_code(m):
    lower, lines = m.name.lower(), []
    for f, off in wire_offsets(m):
        t, name = C_TYPES[f.type], f"mavlink_msg_{lower}_get_{f.name}"
        if f.array:
            lines += [f"/// Copies {f.name} ({f.array} values) to out; returns {f.array}.",
                      f"static inline uint16_t {name}(const mavlink_message_t* msg, {t}* out) {{",
                      f"  memcpy(out, _MAV_PAYLOAD(msg) + {off}, {f.wire});", f"  return {f.array};", "}"]
        else:
            lines += [f"static inline {t} {name}(const mavlink_message_t* msg) {{",
                      f"  {t} v;", f"  memcpy(&v, _MAV_PAYLOAD(msg) + {off}, {f.wire});", "  return v;", "}"]
    return lines


def message_code(m):
    lines = [f"// ---- {m.name} (id {m.id}): {m.length} bytes, CRC_EXTRA {m.crc_extra} ----"]
    for part in (struct_code, pack_code, encode_code, decode_code, getter_code):
        lines += part(m)
    return lines + [""]


def table_code(msgs):
    lines = ["static inline const mavlink_msg_entry_t* mavlink_get_msg_entry(uint32_t msgid) {",
             f"  static const mavlink_msg_entry_t entries[{len(msgs)}] = {{"]
    for m in sorted(msgs, key=lambda m: m.id):
        lines.append(f"      {{{m.id}, {m.crc_extra}, {m.length}, {m.length}}},  // {m.name}")
    lines += ["  };",
              "  for (const mavlink_msg_entry_t& e : entries) {",
              "    if (e.msgid == msgid) return &e;",
              "  }",
              "  return NULL;", "}"]
    return lines


def header_text(path, msgs, enums, version):
    dialect = os.path.splitext(os.path.basename(path))[0]
    lines = [f"// MAVLink 1.0 C API of the {dialect} dialect, generated from {os.path.basename(path)} by",
             "// plugins/fcu_serial/mavlink/generate_c.py (tern). Do not edit. C++ only.",
             "#pragma once", "#ifndef MAVLINK_H", "#define MAVLINK_H", ""]
    with open(CORE) as f:
        lines.append(f.read())
    lines += ["// ---- Enums ----", ""]
    for en in enums:
        lines += enum_code(en)
    lines += ["// MAVLink version sent in HEARTBEAT.mavlink_version (the dialect's <version>, else 2)",
              "#ifndef MAVLINK_VERSION", f"#define MAVLINK_VERSION {version}", "#endif", ""]
    for m in msgs:
        lines += message_code(m)
    lines += ["// ---- The dialect's messages for the parser ----"] + table_code(msgs)
    return "\n".join(lines + ["", "#endif  // MAVLINK_H", ""])


def main(argv):
    if len(argv) != 3:
        raise SystemExit("usage: generate_c.py DIALECT.xml OUT_DIR")
    path, out_dir = argv[1], argv[2]
    root = generate.read_dialect(path)
    msgs, enums = read_messages(root, path), read_enums(root, path)
    text = header_text(path, msgs, enums, dialect_version(root, path))
    dialect = os.path.splitext(os.path.basename(path))[0]
    generate.write_if_changed(os.path.join(out_dir, dialect, "mavlink.h"), text)


if __name__ == "__main__":
    main(sys.argv)
