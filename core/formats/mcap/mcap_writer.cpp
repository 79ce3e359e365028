#include "mcap/mcap_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include <zlib.h>
#include <zstd.h>

#include "mcap/mcap_format.hpp"

namespace tern::core {

namespace mcap {
std::uint32_t crc32(std::string_view data, std::uint32_t crc) {
  return static_cast<std::uint32_t>(::crc32_z(crc, reinterpret_cast<const Bytef*>(data.data()), data.size()));
}
}  // namespace mcap

using mcap::begin_record, mcap::end_record, mcap::Op, mcap::Out;

namespace {

void put_map(std::string& b, const McapWriter::Metadata& m) {
  std::string body;
  for (const auto& [k, v] : m) {
    Out{body}.str(k);
    Out{body}.str(v);
  }
  Out{b}.str(body);  // uint32 byte length, then the pairs
}

}  // namespace

McapWriter::McapWriter(fs::path path, LogHealth& health, Options options) : path_(std::move(path)), health_(health), options_(options) {
  zstd_ = ZSTD_createCCtx();
  if (health_.failed()) return;
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    health_.fail(cannot_write(path_, errno));
    return;
  }
  std::string b(mcap::kMagic, sizeof mcap::kMagic);
  const std::size_t c = begin_record(b, Op::header);
  Out{b}.str("ros2");
  Out{b}.str("tern");
  end_record(b, c);
  write(b);
}

McapWriter::~McapWriter() {
  finish();
  ZSTD_freeCCtx(static_cast<ZSTD_CCtx*>(zstd_));
}

void McapWriter::write(const std::string& bytes) {
  if (fd_ < 0) return;
  if (health_.failed()) {  // another file of the log failed: this one stops too, complete so far
    ::close(fd_);
    fd_ = -1;
    return;
  }
  int err = 0;
  if (::lseek(fd_, static_cast<off_t>(size_), SEEK_SET) < 0) err = errno;
  if (err == 0) write_all(fd_, bytes, err);
  if (err == 0 && provisional_.size() > bytes.size() && ::ftruncate(fd_, static_cast<off_t>(size_ + bytes.size())) != 0) err = errno;
  if (err == 0) {
    size_ += bytes.size();
    provisional_.clear();
    return;
  }
  health_.fail(cannot_write(path_, err));
  restore_provisional();
  ::close(fd_);
  fd_ = -1;
}

void McapWriter::restore_provisional() {
  // cut back to the last complete record; the provisional chunk the failed write overwrote goes
  // back where it was (it fitted there before), so the file keeps every chunk it had
  int err = 0;
  if (::ftruncate(fd_, static_cast<off_t>(size_ + provisional_.size())) == 0 && ::lseek(fd_, static_cast<off_t>(size_), SEEK_SET) >= 0 &&
      write_all(fd_, provisional_, err) == provisional_.size())
    return;
  if (::ftruncate(fd_, static_cast<off_t>(size_)) != 0) {
    // a reader (recover) stops at the partial record
  }
}

void McapWriter::sync() {
  std::lock_guard lk(mu_);
  if (synced_ || fd_ < 0) return;
  std::uint64_t chunk_length = 0;
  std::map<std::uint16_t, std::uint64_t> index_offsets;
  std::string b = chunk_records(chunk_length, index_offsets, false);  // overwritten soon: not worth compressing
  const std::uint64_t keep = size_;
  write(b);  // at size_, over the previous provisional chunk
  if (fd_ < 0) return;
  size_ = keep;
  provisional_ = std::move(b);
  synced_ = true;
}

std::uint16_t McapWriter::add_schema(std::string_view name, std::string_view encoding, std::string_view data) {
  std::lock_guard lk(mu_);
  write_chunk_locked();  // records outside chunks follow the messages written before them
  const auto id = static_cast<std::uint16_t>(++schema_count_);
  std::string b;
  const std::size_t c = begin_record(b, Op::schema);
  Out{b}.u16(id);
  Out{b}.str(name);
  Out{b}.str(encoding);
  Out{b}.str(data);  // uint32 length-prefixed bytes
  end_record(b, c);
  write(b);
  schemas_ += b;
  return id;
}

std::uint16_t McapWriter::add_channel(std::uint16_t schema, std::string_view topic, std::string_view message_encoding,
                                      const Metadata& metadata) {
  std::lock_guard lk(mu_);
  write_chunk_locked();
  if (sequence_.empty()) sequence_.push_back(0);  // ids from 1
  const auto id = static_cast<std::uint16_t>(sequence_.size());
  sequence_.push_back(0);
  channel_counts_.resize(sequence_.size());
  chunk_.index.resize(sequence_.size());
  std::string b;
  const std::size_t c = begin_record(b, Op::channel);
  Out{b}.u16(id);
  Out{b}.u16(schema);
  Out{b}.str(topic);
  Out{b}.str(message_encoding);
  put_map(b, metadata);
  end_record(b, c);
  write(b);
  channels_ += b;
  return id;
}

void McapWriter::message(std::uint16_t channel, std::uint64_t log_time, std::string_view data) {
  std::lock_guard lk(mu_);
  message_locked(channel, log_time, data);
}

void McapWriter::message_locked(std::uint16_t channel, std::uint64_t log_time, std::string_view data) {
  if (fd_ < 0) return;
  std::string& r = chunk_.records;
  chunk_.index[channel].emplace_back(log_time, r.size());
  const std::size_t c = begin_record(r, Op::message);
  Out{r}.u16(channel);
  Out{r}.u32(sequence_[channel]++);
  Out{r}.u64(log_time);
  Out{r}.u64(log_time);  // publish_time
  r.append(data);
  end_record(r, c);
  chunk_.start = std::min(chunk_.start, log_time);
  chunk_.end = std::max(chunk_.end, log_time);
  ++channel_counts_[channel];
  ++messages_;
  synced_ = false;
  if (r.size() >= options_.chunk_bytes) write_chunk_locked();
}

std::string McapWriter::chunk_records(std::uint64_t& chunk_length, std::map<std::uint16_t, std::uint64_t>& index_offsets, bool compress) {
  const std::string& r = chunk_.records;
  if (compress) {
    // the buffer grows to the bound once and is never shrunk: resizing it to each frame and back
    // zero-filled a megabyte per chunk (0.9 % of the default flight's replay-level log, pinned to one core)
    const std::size_t bound = ZSTD_compressBound(r.size());
    if (compressed_.size() < bound) compressed_.resize(bound);
    const std::size_t n =
        ZSTD_compressCCtx(static_cast<ZSTD_CCtx*>(zstd_), compressed_.data(), compressed_.size(), r.data(), r.size(), options_.zstd_level);
    compressed_size_ = ZSTD_isError(n) ? 0 : n;  // cannot fail with a bound-sized buffer
  }
  const std::string_view data = compress ? std::string_view(compressed_.data(), compressed_size_) : std::string_view(r);
  std::string b;
  const std::size_t c = begin_record(b, Op::chunk);
  Out{b}.u64(chunk_.start);
  Out{b}.u64(chunk_.end);
  Out{b}.u64(r.size());
  Out{b}.u32(mcap::crc32(r));
  Out{b}.str(compress ? "zstd" : "");
  Out{b}.u64(data.size());
  b += data;
  end_record(b, c);
  const std::uint64_t chunk_start = size_;
  chunk_length = b.size();
  for (std::size_t id = 0; id < chunk_.index.size(); ++id) {
    const auto& entries = chunk_.index[id];
    if (entries.empty()) continue;
    const auto channel = static_cast<std::uint16_t>(id);
    index_offsets[channel] = chunk_start + b.size();
    const std::size_t m = begin_record(b, Op::message_index);
    Out{b}.u16(channel);
    Out{b}.u32(static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [t, offset] : entries) {
      Out{b}.u64(t);
      Out{b}.u64(offset);
    }
    end_record(b, m);
  }
  return b;
}

void McapWriter::write_chunk_locked() {
  if (chunk_.records.empty() || fd_ < 0) return;
  std::uint64_t chunk_length = 0;
  std::map<std::uint16_t, std::uint64_t> index_offsets;
  const std::uint64_t chunk_start = size_;
  const std::string b = chunk_records(chunk_length, index_offsets, true);
  write(b);
  synced_ = true;
  if (fd_ >= 0) {
    chunk_indexes_ += chunk_index_record(compressed_size_, chunk_start, chunk_length, index_offsets, b.size() - chunk_length);
    ++chunk_count_;
    start_ = std::min(start_, chunk_.start);
    end_ = std::max(end_, chunk_.end);
  }
  chunk_.records.clear();                              // keeps its capacity: the next chunk reuses it
  for (auto& entries : chunk_.index) entries.clear();  // keeps their capacity too
  chunk_.start = UINT64_MAX;
  chunk_.end = 0;
}

std::string McapWriter::chunk_index_record(std::uint64_t compressed_size, std::uint64_t chunk_start, std::uint64_t chunk_length,
                                           const std::map<std::uint16_t, std::uint64_t>& index_offsets, std::uint64_t index_length) const {
  std::string b;
  const std::size_t c = begin_record(b, Op::chunk_index);
  Out{b}.u64(chunk_.start);
  Out{b}.u64(chunk_.end);
  Out{b}.u64(chunk_start);
  Out{b}.u64(chunk_length);
  Out{b}.u32(static_cast<std::uint32_t>(index_offsets.size() * 10));
  for (const auto& [channel, offset] : index_offsets) {
    Out{b}.u16(channel);
    Out{b}.u64(offset);
  }
  Out{b}.u64(index_length);
  Out{b}.str("zstd");
  Out{b}.u64(compressed_size);
  Out{b}.u64(chunk_.records.size());
  end_record(b, c);
  return b;
}

void McapWriter::metadata(std::string_view name, const Metadata& values) {
  std::lock_guard lk(mu_);
  write_chunk_locked();  // records outside chunks follow the messages written before them
  std::string b;
  const std::size_t c = begin_record(b, Op::metadata);
  Out{b}.str(name);
  put_map(b, values);
  end_record(b, c);
  const std::uint64_t offset = size_;
  write(b);
  std::string& ix = metadata_indexes_;
  const std::size_t i = begin_record(ix, Op::metadata_index);
  Out{ix}.u64(offset);
  Out{ix}.u64(b.size());
  Out{ix}.str(name);
  end_record(ix, i);
  ++metadata_count_;
}

void McapWriter::attachment(std::string_view name, std::string_view media_type, std::string_view data, std::uint64_t log_time) {
  std::lock_guard lk(mu_);
  write_chunk_locked();
  std::string b;
  const std::size_t c = begin_record(b, Op::attachment);
  Out{b}.u64(log_time);
  Out{b}.u64(0);  // create_time: no wall-clock time in the file
  Out{b}.str(name);
  Out{b}.str(media_type);
  Out{b}.u64(data.size());
  b.append(data);
  Out{b}.u32(mcap::crc32(std::string_view(b).substr(c)));
  end_record(b, c);
  const std::uint64_t offset = size_;
  write(b);
  std::string& ix = attachment_indexes_;
  const std::size_t i = begin_record(ix, Op::attachment_index);
  Out{ix}.u64(offset);
  Out{ix}.u64(b.size());
  Out{ix}.u64(log_time);
  Out{ix}.u64(0);
  Out{ix}.u64(data.size());
  Out{ix}.str(name);
  Out{ix}.str(media_type);
  end_record(ix, i);
  ++attachment_count_;
}

void McapWriter::write_summary_locked() {
  std::string b;
  const std::size_t d = begin_record(b, Op::data_end);
  Out{b}.u32(0);  // data_section_crc: not computed
  end_record(b, d);
  const std::uint64_t summary_start = size_ + b.size();
  std::string summary, offsets;
  auto group = [&](Op op, const std::string& records) {
    if (records.empty()) return;
    const std::size_t o = begin_record(offsets, Op::summary_offset);
    Out{offsets}.u8(static_cast<std::uint8_t>(op));
    Out{offsets}.u64(summary_start + summary.size());
    Out{offsets}.u64(records.size());
    end_record(offsets, o);
    summary += records;
  };
  std::string stats;
  const std::size_t s = begin_record(stats, Op::statistics);
  Out{stats}.u64(messages_);
  Out{stats}.u16(static_cast<std::uint16_t>(schema_count_));
  Out{stats}.u32(static_cast<std::uint32_t>(sequence_.empty() ? 0 : sequence_.size() - 1));
  Out{stats}.u32(attachment_count_);
  Out{stats}.u32(metadata_count_);
  Out{stats}.u32(chunk_count_);
  Out{stats}.u64(messages_ ? start_ : 0);
  Out{stats}.u64(messages_ ? end_ : 0);
  const auto used = static_cast<std::uint32_t>(channel_counts_.size() - std::count(channel_counts_.begin(), channel_counts_.end(), 0));
  Out{stats}.u32(used * 10);
  for (std::size_t id = 0; id < channel_counts_.size(); ++id) {
    if (channel_counts_[id] == 0) continue;  // a channel without messages is not listed
    Out{stats}.u16(static_cast<std::uint16_t>(id));
    Out{stats}.u64(channel_counts_[id]);
  }
  end_record(stats, s);
  group(Op::schema, schemas_);
  group(Op::channel, channels_);
  group(Op::statistics, stats);
  group(Op::chunk_index, chunk_indexes_);
  group(Op::attachment_index, attachment_indexes_);
  group(Op::metadata_index, metadata_indexes_);
  const std::uint64_t summary_offset_start = summary_start + summary.size();
  std::string tail = summary + offsets;
  Out{tail}.u8(static_cast<std::uint8_t>(Op::footer));
  Out{tail}.u64(8 + 8 + 4);  // the footer's length: its CRC covers it
  Out{tail}.u64(summary_start);
  Out{tail}.u64(summary_offset_start);
  Out{tail}.u32(mcap::crc32(tail));  // from the summary's start through summary_offset_start
  tail.append(mcap::kMagic, sizeof mcap::kMagic);
  write(b + tail);
}

void McapWriter::finish() {
  std::lock_guard lk(mu_);
  if (finished_) return;
  finished_ = true;
  write_chunk_locked();
  if (fd_ < 0) return;
  write_summary_locked();
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

}  // namespace tern::core
