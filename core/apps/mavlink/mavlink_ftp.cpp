// core/apps/mavlink/mavlink_ftp.cpp: read-only MAVLink FTP over files in memory (mavlink_ftp.hpp).
#include "mavlink/mavlink_ftp.hpp"

#include <algorithm>
#include <cstring>

namespace tern::core::mavlink {
namespace {

FtpMessage reply(const FtpMessage& r, std::uint8_t opcode) {
  FtpMessage a;
  a.seq = static_cast<std::uint16_t>(r.seq + 1);
  a.session = r.session;
  a.opcode = opcode;
  a.req_opcode = r.opcode;
  a.offset = r.offset;
  return a;
}

FtpMessage nak(const FtpMessage& r, std::uint8_t error) {
  FtpMessage a = reply(r, MAV_FTP_OPCODE_NAK);
  a.size = 1;
  a.data[0] = error;
  return a;
}

/// The path a request carries (size bytes of data, up to a NUL), without a leading '/'.
std::string path_of(const FtpMessage& r) {
  std::string p(reinterpret_cast<const char*>(r.data.data()), r.size);
  p = p.substr(0, p.find('\0'));
  while (!p.empty() && p.front() == '/') p.erase(0, 1);
  return p;
}

}  // namespace

FtpMessage FtpMessage::parse(const FtpPayload& p) {
  FtpMessage m;
  m.seq = static_cast<std::uint16_t>(p[0] | (p[1] << 8));
  m.session = p[2];
  m.opcode = p[3];
  m.size = p[4];
  m.req_opcode = p[5];
  m.burst_complete = p[6];
  m.offset = static_cast<std::uint32_t>(p[8]) | (static_cast<std::uint32_t>(p[9]) << 8) | (static_cast<std::uint32_t>(p[10]) << 16) |
             (static_cast<std::uint32_t>(p[11]) << 24);
  std::copy(p.begin() + kFtpHeader, p.end(), m.data.begin());
  return m;
}

FtpPayload FtpMessage::pack() const {
  FtpPayload p{};
  p[0] = static_cast<std::uint8_t>(seq & 0xFF);
  p[1] = static_cast<std::uint8_t>(seq >> 8);
  p[2] = session;
  p[3] = opcode;
  p[4] = size;
  p[5] = req_opcode;
  p[6] = burst_complete;
  for (int k = 0; k < 4; ++k) p[8 + k] = static_cast<std::uint8_t>(offset >> (8 * k));
  std::copy(data.begin(), data.end(), p.begin() + kFtpHeader);
  return p;
}

FtpServer::FtpServer(std::map<std::string, std::string> files) : files_(std::move(files)) {}

std::vector<FtpPayload> FtpServer::answer(const FtpPayload& request) {
  const FtpMessage r = FtpMessage::parse(request);
  if (last_seq_ && *last_seq_ == r.seq) return last_answer_;  // the GCS missed our answer: the same again
  last_answer_.clear();
  for (const FtpMessage& m : serve(r)) last_answer_.push_back(m.pack());
  last_seq_ = r.seq;
  return last_answer_;
}

std::vector<FtpMessage> FtpServer::serve(const FtpMessage& r) {
  if (r.size > kFtpData) return {nak(r, MAV_FTP_ERR_INVALIDDATASIZE)};
  switch (r.opcode) {
    case MAV_FTP_OPCODE_NONE: return {reply(r, MAV_FTP_OPCODE_ACK)};
    case MAV_FTP_OPCODE_TERMINATESESSION:
      if (!file_of(r.session)) return {nak(r, MAV_FTP_ERR_INVALIDSESSION)};
      sessions_[r.session].reset();
      return {reply(r, MAV_FTP_OPCODE_ACK)};
    case MAV_FTP_OPCODE_RESETSESSION:
      for (auto& s : sessions_) s.reset();
      return {reply(r, MAV_FTP_OPCODE_ACK)};
    case MAV_FTP_OPCODE_LISTDIRECTORY: return {list(r)};
    case MAV_FTP_OPCODE_OPENFILERO: return {open(r)};
    case MAV_FTP_OPCODE_READFILE: return {read(r, r.offset)};
    case MAV_FTP_OPCODE_BURSTREADFILE: {
      std::vector<FtpMessage> out;
      std::uint32_t offset = r.offset;
      for (FtpMessage m = read(r, offset);; m = read(r, offset)) {
        m.seq = static_cast<std::uint16_t>(r.seq + 1 + out.size());
        const bool last = m.opcode == MAV_FTP_OPCODE_NAK || offset + m.size >= file_of(r.session)->size();
        m.burst_complete = last ? 1 : 0;
        offset += m.opcode == MAV_FTP_OPCODE_ACK ? m.size : 0;
        out.push_back(m);
        if (last) return out;
      }
    }
    default: return {nak(r, MAV_FTP_ERR_UNKNOWNCOMMAND)};
  }
}

const std::string* FtpServer::file_of(std::uint8_t session) const {
  if (session >= kMaxSessions || !sessions_[session]) return nullptr;
  return &files_.at(*sessions_[session]);
}

FtpMessage FtpServer::list(const FtpMessage& r) const {
  const std::string dir = path_of(r);
  if (!dir.empty() && dir != ".") return nak(r, MAV_FTP_ERR_FILENOTFOUND);  // one directory: the root
  FtpMessage a = reply(r, MAV_FTP_OPCODE_ACK);
  std::size_t index = 0, used = 0;
  for (const auto& [name, contents] : files_) {
    if (index++ < r.offset) continue;
    const std::string entry = "F" + name + "\t" + std::to_string(contents.size());
    if (used + entry.size() + 1 > kFtpData) break;
    std::memcpy(a.data.data() + used, entry.c_str(), entry.size() + 1);
    used += entry.size() + 1;
  }
  if (used == 0) return nak(r, MAV_FTP_ERR_EOF);
  a.size = static_cast<std::uint8_t>(used);
  return a;
}

FtpMessage FtpServer::open(const FtpMessage& r) {
  const std::string name = path_of(r);
  const auto f = files_.find(name);
  if (f == files_.end()) return nak(r, MAV_FTP_ERR_FILENOTFOUND);
  const auto free = std::find_if(sessions_.begin(), sessions_.end(), [](const auto& s) { return !s.has_value(); });
  if (free == sessions_.end()) return nak(r, MAV_FTP_ERR_NOSESSIONSAVAILABLE);
  *free = name;
  FtpMessage a = reply(r, MAV_FTP_OPCODE_ACK);
  a.session = static_cast<std::uint8_t>(free - sessions_.begin());
  a.offset = 0;
  a.size = 4;
  const auto size = static_cast<std::uint32_t>(f->second.size());
  for (int k = 0; k < 4; ++k) a.data[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(size >> (8 * k));
  return a;
}

FtpMessage FtpServer::read(const FtpMessage& r, std::uint32_t offset) const {
  const std::string* file = file_of(r.session);
  if (!file) return nak(r, MAV_FTP_ERR_INVALIDSESSION);
  if (offset >= file->size()) return nak(r, MAV_FTP_ERR_EOF);
  FtpMessage a = reply(r, MAV_FTP_OPCODE_ACK);
  a.offset = offset;
  const std::size_t want = r.opcode == MAV_FTP_OPCODE_READFILE && r.size > 0 ? r.size : kFtpData;
  const std::size_t n = std::min({want, kFtpData, file->size() - offset});
  std::memcpy(a.data.data(), file->data() + offset, n);
  a.size = static_cast<std::uint8_t>(n);
  return a;
}

}  // namespace tern::core::mavlink
