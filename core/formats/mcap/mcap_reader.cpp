#include "mcap/mcap_reader.hpp"

#include <cstring>
#include <limits>

#include <fmt/format.h>
#include <zstd.h>
#include <memory>

#include "tern/input_file.hpp"

namespace tern::core {

using mcap::In, mcap::Op;

namespace {
const char* op_name(Op op) {
  switch (op) {
    case Op::header: return "header";
    case Op::footer: return "footer";
    case Op::schema: return "schema";
    case Op::channel: return "channel";
    case Op::message: return "message";
    case Op::chunk: return "chunk";
    case Op::message_index: return "message index";
    case Op::chunk_index: return "chunk index";
    case Op::attachment: return "attachment";
    case Op::attachment_index: return "attachment index";
    case Op::statistics: return "statistics";
    case Op::metadata: return "metadata";
    case Op::metadata_index: return "metadata index";
    case Op::summary_offset: return "summary offset";
    case Op::data_end: return "data end";
  }
  return "unknown";
}

std::map<std::string, std::string> read_map(In& in) {
  std::map<std::string, std::string> m;
  const std::string_view body = in.bytes(in.u32());
  In kv{body.data(), body.data() + body.size()};
  while (kv.ok && kv.left() > 0) {
    std::string k = kv.str();
    std::string v = kv.str();
    if (kv.ok) m[std::move(k)] = std::move(v);
  }
  return m;
}
}  // namespace

McapReader::McapReader(fs::path path) : path_(std::move(path)) {
  // a regular file only: a device (/dev/zero) or a FIFO has no size to check records against
  if (const std::string p = input_file_problem(path_, std::numeric_limits<std::uintmax_t>::max()); !p.empty() && fs::exists(path_))
    throw McapError(fmt::format("{}: {}", printable(path_.string()), p));
  in_.open(path_, std::ios::binary);
  if (!in_) throw McapError(fmt::format("{}: cannot open: {}", path_.string(), std::strerror(errno)));
  std::error_code ec;
  size_ = fs::file_size(path_, ec);
  char magic[sizeof mcap::kMagic];
  if (!in_.read(magic, sizeof magic) || std::memcmp(magic, mcap::kMagic, sizeof magic) != 0)
    throw McapError(fmt::format("{}: not an MCAP file (no magic at byte 0)", path_.string()));
  offset_ = sizeof magic;
  McapRecord h;
  if (!next(h) || h.op != Op::header) throw McapError(fmt::format("{}: byte 8: expected the header record", path_.string()));
}

bool McapReader::next(McapRecord& r) {
  char prefix[mcap::kRecordPrefix];
  if (!in_.read(prefix, sizeof prefix)) {
    truncated_ = fmt::format("the file ends at byte {} without a data end record", size_);
    return false;
  }
  r.op = static_cast<Op>(prefix[0]);
  std::uint64_t n;
  std::memcpy(&n, prefix + 1, 8);
  r.offset = offset_;
  if (n > size_ - offset_ - sizeof prefix) {
    truncated_ = fmt::format("the file ends at byte {} inside a {} record (byte {}, {} bytes long)", size_, op_name(r.op), offset_, n);
    return false;
  }
  r.content.resize(n);
  if (!in_.read(r.content.data(), static_cast<std::streamsize>(n))) {
    truncated_ = fmt::format("cannot read the {} record at byte {}", op_name(r.op), offset_);
    return false;
  }
  offset_ += sizeof prefix + n;
  return r.op != Op::data_end && r.op != Op::footer;
}

void McapReader::damaged(std::uint64_t offset, const std::string& what) const {
  throw McapError(fmt::format("{}: byte {}: {}", path_.string(), offset, what));
}

McapSchema McapReader::schema(const McapRecord& r) const {
  In in{r.content.data(), r.content.data() + r.content.size()};
  McapSchema s;
  s.id = in.u16();
  s.name = in.str();
  s.encoding = in.str();
  s.data = in.str();
  if (!in.ok) damaged(r.offset, "schema record too short");
  return s;
}

McapChannel McapReader::channel(const McapRecord& r) const {
  In in{r.content.data(), r.content.data() + r.content.size()};
  McapChannel c;
  c.id = in.u16();
  c.schema = in.u16();
  c.topic = in.str();
  c.message_encoding = in.str();
  c.metadata = read_map(in);
  if (!in.ok) damaged(r.offset, "channel record too short");
  return c;
}

McapAttachment McapReader::attachment(const McapRecord& r) const {
  In in{r.content.data(), r.content.data() + r.content.size()};
  McapAttachment a;
  a.log_time = in.u64();
  a.create_time = in.u64();
  a.name = in.str();
  a.media_type = in.str();
  a.data = std::string(in.bytes(in.u64()));
  if (!in.ok) damaged(r.offset, "attachment record too short");
  return a;
}

McapMetadata McapReader::metadata(const McapRecord& r) const {
  In in{r.content.data(), r.content.data() + r.content.size()};
  McapMetadata m;
  m.name = in.str();
  m.values = read_map(in);
  if (!in.ok) damaged(r.offset, "metadata record too short");
  return m;
}

McapMessage McapReader::message(std::string_view content, std::uint64_t offset) const {
  In in{content.data(), content.data() + content.size()};
  McapMessage m;
  m.channel = in.u16();
  m.sequence = in.u32();
  m.log_time = in.u64();
  m.publish_time = in.u64();
  if (!in.ok) damaged(offset, "message record too short");
  m.data = std::string_view(in.p, in.left());
  return m;
}

void McapReader::unpack_zstd(std::uint64_t offset, std::string_view frame, std::uint64_t size, std::string& buffer) const {
  // streamed into a buffer that grows with what the frame gives (doubling from 1 MiB, never past
  // the declared size): a few bytes declaring gigabytes take no more memory than they unpack to
  const std::unique_ptr<ZSTD_DCtx, std::size_t (*)(ZSTD_DCtx*)> dctx(ZSTD_createDCtx(), ZSTD_freeDCtx);
  buffer.resize(static_cast<std::size_t>(std::min<std::uint64_t>(size, std::uint64_t{1} << 20)));
  ZSTD_inBuffer in{frame.data(), frame.size(), 0};
  ZSTD_outBuffer out{buffer.data(), buffer.size(), 0};
  std::size_t left = 1;  // ZSTD_decompressStream: 0 once the frame is complete
  for (;;) {
    left = ZSTD_decompressStream(dctx.get(), &out, &in);
    if (ZSTD_isError(left)) damaged(offset, fmt::format("chunk does not decompress (zstd: {})", ZSTD_getErrorName(left)));
    if (left == 0) break;
    if (out.pos < out.size) {
      if (in.pos == in.size) break;  // the frame ends before it is complete
      continue;
    }
    if (out.size >= size) break;  // the declared size reached and the frame goes on
    buffer.resize(static_cast<std::size_t>(std::min<std::uint64_t>(size, 2 * std::uint64_t{out.size})));
    out.dst = buffer.data(), out.size = buffer.size();
  }
  if (left != 0 || out.pos != size)
    damaged(offset, fmt::format("chunk does not decompress (zstd: {} bytes of the {} declared{})", out.pos, size,
                                left != 0 ? ", the frame incomplete or longer" : ""));
  buffer.resize(out.pos);
}

void McapReader::chunk_messages(const McapRecord& r, std::string& buffer, const std::function<void(const McapMessage&)>& each) const {
  In in{r.content.data(), r.content.data() + r.content.size()};
  in.u64();  // message_start_time
  in.u64();  // message_end_time
  const std::uint64_t size = in.u64();
  const std::uint32_t crc = in.u32();
  const std::string compression = in.str();
  const std::string_view data = in.bytes(in.u64());
  if (!in.ok) damaged(r.offset, "chunk record too short");
  if (size > mcap::kMaxChunkBytes)
    damaged(r.offset,
            fmt::format("chunk declares {} bytes uncompressed, more than the {} this reader unpacks", size, mcap::kMaxChunkBytes));
  if (compression == "zstd") {
    const unsigned long long frame = ZSTD_getFrameContentSize(data.data(), data.size());
    if (frame != ZSTD_CONTENTSIZE_UNKNOWN && frame != ZSTD_CONTENTSIZE_ERROR && frame != size)
      damaged(r.offset, fmt::format("chunk declares {} bytes uncompressed, its zstd frame {}", size, frame));
    unpack_zstd(r.offset, data, size, buffer);
  } else if (compression.empty()) {
    buffer.assign(data);
  } else {
    damaged(r.offset, fmt::format("chunk compression '{}' (this reader knows zstd and none)", compression));
  }
  if (crc != 0 && mcap::crc32(buffer) != crc) damaged(r.offset, "chunk's CRC-32 does not match its records");
  In rec{buffer.data(), buffer.data() + buffer.size()};
  while (rec.left() > 0) {
    const auto op = static_cast<Op>(rec.u8());
    const std::string_view content = rec.bytes(rec.u64());
    if (!rec.ok) damaged(r.offset, "a record inside the chunk runs past its end");
    if (op == Op::message) each(message(content, r.offset));
  }
}

}  // namespace tern::core
