#include "mcap/mcap_recover.hpp"

#include <map>

#include <fmt/format.h>

#include "mcap/mcap_reader.hpp"
#include "mcap/mcap_writer.hpp"

namespace tern::core {

namespace {

/// Copies one record of the input's data section into `out`, ids mapped to the output's.
struct Copier {
  McapReader& in;
  McapWriter& out;
  RecoverReport& report;
  std::map<std::uint16_t, std::uint16_t> schemas, channels;
  std::string buffer;

  void message(const McapMessage& m) {
    const auto c = channels.find(m.channel);
    if (c == channels.end()) return;  // a channel the file never declared: nothing to read it with
    out.message(c->second, m.log_time, m.data);
    ++report.messages;
  }
  void copy(const McapRecord& r) {
    switch (r.op) {
      case mcap::Op::schema: {
        const McapSchema s = in.schema(r);
        schemas[s.id] = out.add_schema(s.name, s.encoding, s.data);
        break;
      }
      case mcap::Op::channel: {
        const McapChannel c = in.channel(r);
        const auto s = schemas.find(c.schema);
        channels[c.id] = out.add_channel(s == schemas.end() ? 0 : s->second, c.topic, c.message_encoding, c.metadata);
        break;
      }
      case mcap::Op::message: message(in.message(r.content, r.offset)); break;
      case mcap::Op::chunk:
        in.chunk_messages(r, buffer, [this](const McapMessage& m) { message(m); });
        ++report.chunks;
        break;
      case mcap::Op::attachment: {
        const McapAttachment a = in.attachment(r);
        out.attachment(a.name, a.media_type, a.data, a.log_time);
        ++report.attachments;
        break;
      }
      case mcap::Op::metadata: {
        const McapMetadata m = in.metadata(r);
        out.metadata(m.name, m.values);
        break;
      }
      default: break;  // indexes and statistics: the writer makes its own
    }
  }
};

}  // namespace

RecoverReport recover_mcap(const fs::path& in_path, const fs::path& out_path, std::size_t chunk_bytes) {
  McapReader in(in_path);
  LogHealth health;
  RecoverReport report;
  {
    McapWriter out(out_path, health, McapWriter::Options{chunk_bytes});
    Copier copier{in, out, report, {}, {}, {}};
    McapRecord r;
    try {
      while (in.next(r)) copier.copy(r);
      report.stopped = in.truncated();
    } catch (const McapError& e) {  // a damaged chunk: what came before it is kept
      report.stopped = e.what();
    }
    out.finish();
  }
  if (health.failed()) throw McapError(health.error());
  return report;
}

}  // namespace tern::core
