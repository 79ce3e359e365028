// core/apps/mavlink/mavlink_ftp.hpp: the vehicle's side of MAVLink FTP
// (https://mavlink.io/en/services/ftp.html), read-only, over files held in memory: how a ground
// station downloads tern's component metadata (component_metadata.hpp). Pure: payloads in,
// payloads out; the link (gcs_link.cpp) wraps them in FILE_TRANSFER_PROTOCOL messages.
//
// Payload (251 bytes, little-endian): seq_number u16, session u8, opcode u8, size u8, req_opcode u8,
// burst_complete u8, padding u8, offset u32, data[239].
// Served opcodes: None (ACK), TerminateSession, ResetSessions, ListDirectory (the root, "" or "/":
// "F<name>\t<size>" entries from index `offset`), OpenFileRO (path in data, a leading '/' optional:
// ACK with the session and the file's size as u32), ReadFile (size bytes at offset, at most 239),
// BurstReadFile (every chunk from offset to the end, burst_complete on the last). Everything else,
// writes included, is NAK UnknownCommand. NAK data[0] is the MAV_FTP_ERR: EOF past the end,
// FileNotFound, InvalidSession, NoSessionsAvailable (at most kMaxSessions open), InvalidDataSize
// (a size field beyond the payload). Each answer's seq_number is the request's plus one; a request
// repeating the last one's seq_number gets the last answer again (the spec's resend rule).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace tern::core::mavlink {

inline constexpr std::size_t kFtpPayload = 251;                    ///< FILE_TRANSFER_PROTOCOL.payload
inline constexpr std::size_t kFtpHeader = 12;                      ///< the header above
inline constexpr std::size_t kFtpData = kFtpPayload - kFtpHeader;  ///< 239

// MAV_FTP_OPCODE and MAV_FTP_ERR (common.xml)
inline constexpr std::uint8_t MAV_FTP_OPCODE_NONE = 0, MAV_FTP_OPCODE_TERMINATESESSION = 1, MAV_FTP_OPCODE_RESETSESSION = 2,
                              MAV_FTP_OPCODE_LISTDIRECTORY = 3, MAV_FTP_OPCODE_OPENFILERO = 4, MAV_FTP_OPCODE_READFILE = 5,
                              MAV_FTP_OPCODE_BURSTREADFILE = 15, MAV_FTP_OPCODE_ACK = 128, MAV_FTP_OPCODE_NAK = 129;
inline constexpr std::uint8_t MAV_FTP_ERR_FAIL = 1, MAV_FTP_ERR_INVALIDDATASIZE = 3, MAV_FTP_ERR_INVALIDSESSION = 4,
                              MAV_FTP_ERR_NOSESSIONSAVAILABLE = 5, MAV_FTP_ERR_EOF = 6, MAV_FTP_ERR_UNKNOWNCOMMAND = 7,
                              MAV_FTP_ERR_FILENOTFOUND = 10;

using FtpPayload = std::array<std::uint8_t, kFtpPayload>;

/// The header's fields (a view of a payload's first 12 bytes and its data).
struct FtpMessage {
  std::uint16_t seq = 0;
  std::uint8_t session = 0, opcode = 0, size = 0, req_opcode = 0, burst_complete = 0;
  std::uint32_t offset = 0;
  std::array<std::uint8_t, kFtpData> data{};
  static FtpMessage parse(const FtpPayload& p);
  FtpPayload pack() const;
};

class FtpServer {
 public:
  static constexpr std::size_t kMaxSessions = 4;
  /// `files`: name (no leading '/') -> contents.
  explicit FtpServer(std::map<std::string, std::string> files);
  /// The answers to one request (one, or a BurstReadFile's chunks).
  std::vector<FtpPayload> answer(const FtpPayload& request);

 private:
  std::vector<FtpMessage> serve(const FtpMessage& r);
  FtpMessage list(const FtpMessage& r) const;
  FtpMessage open(const FtpMessage& r);
  FtpMessage read(const FtpMessage& r, std::uint32_t offset) const;
  const std::string* file_of(std::uint8_t session) const;

  std::map<std::string, std::string> files_;
  std::array<std::optional<std::string>, kMaxSessions> sessions_;  // the file each open session reads
  std::optional<std::uint16_t> last_seq_;
  std::vector<FtpPayload> last_answer_;
};

}  // namespace tern::core::mavlink
