// core/apps/mavlink/mavlink_messages.hpp: the common-dialect messages tern sends and reads: the
// structs generated at build time from common.xml (mavlink/common_messages.hpp, by
// sdk/mavlink/generate.py; field names and units are the XML's, the payloads packed in MAVLink's
// wire order), the enum values tern uses (mavlink_enums.hpp), and STATUSTEXT's chunks.
//
// Source: github.com/mavlink/mavlink message_definitions/v1.0/common.xml (and the standard.xml and
// minimal.xml it includes) at commit de1e078a, in sdk/mavlink/message_definitions/. The unit test
// (core/apps/mavlink/tests/test_mavlink_codec.cpp) checks the generated CRC_EXTRA values and
// lengths against tests/mavlink/crc_extra_common.txt, which tests/mavlink/crc_extra_from_xml.py
// computes independently from that XML.
//
// Errors: none thrown.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mavlink/common_messages.hpp"
#include "mavlink/mavlink_enums.hpp"

namespace tern::core::mavlink {

/// A text as STATUSTEXT chunks (common.xml: a text of at most 50 chars is one message with id 0; a
/// longer one is cut into 50-char chunks with `id` (non-zero) and chunk_seq 0, 1, ...; a NUL in a
/// chunk ends the text, so one whose length is a multiple of 50 gets an empty last chunk).
std::vector<Statustext> statustext_chunks(std::uint8_t severity, const std::string& text, std::uint16_t id);
}  // namespace tern::core::mavlink
