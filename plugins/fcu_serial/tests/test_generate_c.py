#!/usr/bin/env python3
"""mavlink/generate_c.py on small dialects: mavgen's enum numbering (implicit values, sorting,
ENUM_END), <extensions/> dropped in wire protocol 1.0, <version>, and one clear error line for
bad input. The generated API itself is tested against tern's codec by test_mavlink_c.cpp."""
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "mavlink"))
import generate_c  # noqa: E402

ENUMS = """<?xml version="1.0"?>
<mavlink>
  <version>3</version>
  <enums>
    <enum name="COUNTED">
      <entry name="COUNTED_A"/>
      <entry value="5" name="COUNTED_B"/>
      <entry name="COUNTED_C"/>
      <entry value="0x2" name="COUNTED_D"/>
    </enum>
  </enums>
  <messages>
    <message id="7" name="EXTENDED">
      <field type="uint8_t" name="a">first</field>
      <field type="float" name="b">second</field>
      <extensions/>
      <field type="double" name="c">a MAVLink 2 extension</field>
    </message>
  </messages>
</mavlink>
"""


def generate(xml_text, name="test_dialect"):
    """Runs generate_c.py's main on xml_text; returns the header text."""
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, name + ".xml")
        with open(path, "w") as f:
            f.write(xml_text)
        generate_c.main(["generate_c.py", path, os.path.join(d, "out")])
        with open(os.path.join(d, "out", name, "mavlink.h")) as f:
            return f.read()


def error_of(xml_text):
    try:
        generate(xml_text)
    except SystemExit as e:
        return str(e)
    raise AssertionError("no error")


class EnumsAndMessages(unittest.TestCase):
    def test_implicit_values_count_up_from_the_highest_so_far(self):
        h = generate(ENUMS)
        body = h[h.index("typedef enum COUNTED {"):h.index("} COUNTED;")]
        # A has no value: highest so far (0) + 1; C follows B (5); sorted by value; END = max + 1
        want = ["COUNTED_A = 1,", "COUNTED_D = 2,", "COUNTED_B = 5,", "COUNTED_C = 6,", "COUNTED_ENUM_END = 7,"]
        self.assertEqual([line.strip() for line in body.splitlines()[1:]], want)

    def test_extensions_are_not_part_of_a_1_0_message(self):
        h = generate(ENUMS)
        self.assertIn("#define MAVLINK_MSG_ID_EXTENDED_LEN 5", h)
        self.assertNotIn("double c", h)
        self.assertIn("mavlink_message_t* msg, uint8_t a, float b) {", h)

    def test_version_tag_sets_mavlink_version(self):
        self.assertIn("#define MAVLINK_VERSION 3", generate(ENUMS))
        self.assertIn("#define MAVLINK_VERSION 2", generate(ENUMS.replace("<version>3</version>", "")))

    def test_rosflight_dialect_is_written_once(self):
        xml = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "mavlink", "rosflight.xml")
        with tempfile.TemporaryDirectory() as d:
            generate_c.main(["generate_c.py", xml, d])
            header = os.path.join(d, "rosflight", "mavlink.h")
            os.utime(header, (1, 1))
            generate_c.main(["generate_c.py", xml, d])  # unchanged: not rewritten (no rebuild)
            self.assertEqual(os.stat(header).st_mtime, 1)
            with open(header) as f:
                text = f.read()
        self.assertEqual(text.count("#define HAVE_ENUM_"), 13)
        for part in ("_pack(uint8_t system_id", "_pack_chan(uint8_t system_id", "_encode(uint8_t system_id", "_decode(const mavlink_message_t*"):
            self.assertEqual(text.count(part), 25, part)


class BadInput(unittest.TestCase):
    def test_unknown_field_type(self):
        msg = error_of(ENUMS.replace('type="float"', 'type="float32"'))
        self.assertIn("test_dialect.xml: message EXTENDED: field b: unknown type float32", msg)

    def test_bad_enum_value(self):
        msg = error_of(ENUMS.replace('value="5"', 'value="five"'))
        self.assertIn("enum COUNTED, entry COUNTED_B: value 'five' is not an integer", msg)

    def test_duplicate_message_id(self):
        dup = ENUMS.replace("</messages>", '<message id="7" name="AGAIN"><field type="uint8_t" name="x"/></message></messages>')
        self.assertIn("message AGAIN: id 7 is already EXTENDED", error_of(dup))

    def test_include_is_refused(self):
        self.assertIn("<include>common.xml</include> is not supported", error_of(ENUMS.replace("<enums>", "<include>common.xml</include><enums>")))

    def test_malformed_xml(self):
        self.assertIn("cannot read the dialect", error_of(ENUMS.replace("</enums>", "")))


if __name__ == "__main__":
    unittest.main()
