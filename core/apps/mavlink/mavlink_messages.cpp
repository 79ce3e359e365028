// core/apps/mavlink/mavlink_messages.cpp: STATUSTEXT's chunks (mavlink_messages.hpp).
#include "mavlink/mavlink_messages.hpp"

#include "tern/mavlink/fields.hpp"

namespace tern::core::mavlink {

namespace {
Statustext chunk(std::uint8_t severity, const std::string& text, std::uint16_t id, std::size_t seq) {
  Statustext t;
  t.severity = severity;
  t.text = ::tern::mavlink::to_chars<50>(text);
  t.id = id;
  t.chunk_seq = static_cast<std::uint8_t>(seq);
  return t;
}
}  // namespace

std::vector<Statustext> statustext_chunks(std::uint8_t severity, const std::string& text, std::uint16_t id) {
  if (text.size() <= 50) return {chunk(severity, text, 0, 0)};
  std::vector<Statustext> out;
  for (std::size_t at = 0; at < text.size() && out.size() < 255; at += 50)
    out.push_back(chunk(severity, text.substr(at, 50), id, out.size()));
  if (text.size() % 50 == 0 && out.size() < 256) out.push_back(chunk(severity, "", id, out.size()));
  return out;
}

}  // namespace tern::core::mavlink
