// tern_fcu_serial/codec.hpp: MAVLink 1.0 framing for the ROSflight dialect (rosflight.xml).
//
// Frame: 0xFE, payload length, sequence, system id, component id, message id, payload,
// checksum (X.25 over length..payload, then the message's CRC_EXTRA; little-endian): the SDK's
// tern/mavlink/frame.hpp writes and checks it. The message structs, their wire order and
// CRC_EXTRA come from rosflight.xml (generated at build time by sdk/mavlink/generate.py into
// tern_fcu_serial/messages.hpp).
//
// Parser: a byte-at-a-time state machine. It never throws and never allocates after
// construction. A frame whose header names an unknown message id or a length that does not
// match the definition, or whose checksum is wrong, is dropped and the bytes after its start
// byte are scanned again (so a truncated frame does not swallow the valid frame after it). Each
// kind of error is counted in ParserStats. Plain C++, no tern host types.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "tern/mavlink/fields.hpp"
#include "tern/mavlink/frame.hpp"
#include "tern_fcu_serial/messages.hpp"

namespace tern::fcu::mavlink {

using ::tern::mavlink::crc_accumulate;
using ::tern::mavlink::crc_calculate;
using ::tern::mavlink::kCrcInit;
using ::tern::mavlink::to_chars;
using ::tern::mavlink::to_string;
inline constexpr std::uint8_t kStx = ::tern::mavlink::kStxV1;                   ///< MAVLink 1.0 start byte
inline constexpr std::size_t kHeaderLength = ::tern::mavlink::kHeaderLengthV1;  ///< STX len seq sys comp msgid
inline constexpr std::size_t kMaxFrameLength = kHeaderLength + 255 + 2;

/// Dialect entry of a message id, or nullptr if rosflight.xml does not define it.
const MessageInfo* find_message(std::uint8_t id);

/// One received frame (payload valid for `len` bytes).
struct Frame {
  std::uint8_t len = 0, seq = 0, sysid = 0, compid = 0, msgid = 0;
  std::array<std::uint8_t, 255> payload{};
};

/// What the parser saw. Bytes that belong to no valid frame are counted once in `skipped`.
struct ParserStats {
  std::uint64_t bytes = 0;       ///< bytes fed
  std::uint64_t frames = 0;      ///< valid frames delivered
  std::uint64_t skipped = 0;     ///< bytes dropped while looking for a frame (garbage, bad frames)
  std::uint64_t bad_crc = 0;     ///< frames with a wrong checksum
  std::uint64_t unknown_id = 0;  ///< headers naming a message id outside the dialect
  std::uint64_t bad_length = 0;  ///< headers whose length does not match the message definition
  /// Frames lost according to the sequence numbers, counted on one counter for the link: a
  /// MAVLink sender numbers every frame of its channel on one counter whatever the ids in the
  /// header (mavlink_helpers.h mavlink_finalize_message_chan). ROSflight sends PARAM_VALUE as
  /// component 0 and the rest as 250 (mavlink_adapter.cpp send_param_value_*), and its buffered
  /// log lines (STATUSTEXT sent once a companion is connected) with the low byte of its
  /// microsecond clock as the system id (comm_manager.cpp send_buffered_log_messages passes
  /// clock_micros() as system_id): all on the one counter. A link carries one FCU.
  std::uint64_t seq_gaps = 0;
};

class Parser {
 public:
  /// Feeds n bytes; calls on_frame(const Frame&) for every valid frame, in order.
  template <class F>
  void feed(const std::uint8_t* data, std::size_t n, F&& on_frame) {
    for (std::size_t i = 0; i < n; ++i) {
      ++stats_.bytes;
      consume(data[i], on_frame);
      while (replay_size_ > 0) {
        const std::uint8_t b = replay_[replay_head_];
        replay_head_ = (replay_head_ + 1) % replay_.size();
        --replay_size_;
        consume(b, on_frame);
      }
    }
  }
  const ParserStats& stats() const { return stats_; }
  /// Drops a partial frame (e.g. after the link was reopened); the counters are kept.
  void reset() {
    state_ = State::idle;
    n_ = 0;
    replay_size_ = 0;
  }

 private:
  enum class State { idle, header, payload };
  template <class F>
  void consume(std::uint8_t b, F& on_frame) {
    switch (state_) {
      case State::idle:
        if (b == kStx) {
          buf_[0] = b;
          n_ = 1;
          state_ = State::header;
        } else {
          ++stats_.skipped;
        }
        return;
      case State::header:
        buf_[n_++] = b;
        if (n_ == kHeaderLength) {
          info_ = find_message(buf_[5]);
          if (info_ == nullptr) {
            ++stats_.unknown_id;
            return fail();
          }
          if (info_->length != buf_[1]) {
            ++stats_.bad_length;
            return fail();
          }
          state_ = State::payload;
        }
        return;
      case State::payload:
        buf_[n_++] = b;
        if (n_ == kHeaderLength + buf_[1] + 2) {
          if (!::tern::mavlink::checksum_matches(buf_.data(), n_ - 2, info_->crc_extra)) {
            ++stats_.bad_crc;
            return fail();
          }
          deliver(on_frame);
        }
        return;
    }
  }
  template <class F>
  void deliver(F& on_frame) {
    frame_.len = buf_[1];
    frame_.seq = buf_[2];
    frame_.sysid = buf_[3];
    frame_.compid = buf_[4];
    frame_.msgid = buf_[5];
    for (std::size_t i = 0; i < frame_.len; ++i) frame_.payload[i] = buf_[kHeaderLength + i];
    if (seen_) stats_.seq_gaps += static_cast<std::uint8_t>(frame_.seq - last_seq_ - 1);
    seen_ = true;
    last_seq_ = frame_.seq;
    ++stats_.frames;
    state_ = State::idle;
    n_ = 0;
    on_frame(static_cast<const Frame&>(frame_));
  }
  /// The frame starting at buf_[0] is invalid: drop its start byte, scan the rest again.
  void fail() {
    ++stats_.skipped;
    // Bytes waiting for replay all come from one candidate frame plus what remained of the
    // previous replay, which was itself inside that frame: never more than one frame's length.
    for (std::size_t i = n_; i-- > 1;) {
      replay_head_ = (replay_head_ + replay_.size() - 1) % replay_.size();
      replay_[replay_head_] = buf_[i];
      ++replay_size_;
    }
    n_ = 0;
    state_ = State::idle;
  }

  State state_ = State::idle;
  std::array<std::uint8_t, kMaxFrameLength> buf_{};
  std::size_t n_ = 0;
  const MessageInfo* info_ = nullptr;
  Frame frame_;
  std::array<std::uint8_t, 2 * kMaxFrameLength> replay_{};  ///< ring buffer of bytes to scan again
  std::size_t replay_head_ = 0, replay_size_ = 0;
  ParserStats stats_;
  bool seen_ = false;  ///< a frame has been seen (its sequence number is last_seq_)
  std::uint8_t last_seq_ = 0;
};

/// The messages tern decodes and encodes (issue 9's list).
using Message = std::variant<SmallImu, SmallMag, SmallBaro, DiffPressure, RosflightGnss, RcChannels, RosflightStatus, AttitudeQuaternion,
                             RosflightOutputRaw, ParamValue, RosflightCmdAck, RosflightVersion, Statustext, Timesync, Heartbeat,
                             OffboardControl, ParamRequestList, ParamRequestRead, ParamSet, RosflightCmd>;

/// The typed message in a valid frame, or nullopt for a dialect message tern does not use.
std::optional<Message> decode(const Frame& f);

/// Writes one frame carrying msg to out (which must hold kHeaderLength + T::kLength + 2 bytes);
/// returns the frame length.
template <class T>
std::size_t encode(const T& msg, std::uint8_t seq, std::uint8_t sysid, std::uint8_t compid, std::uint8_t* out) {
  msg.pack(out + kHeaderLength);
  return ::tern::mavlink::finish_frame_v1(out, T::kLength, seq, sysid, compid, T::kId, T::kCrcExtra);
}

/// A sender: its system/component ids and its sequence counter.
class Encoder {
 public:
  Encoder(std::uint8_t sysid, std::uint8_t compid) : sysid_(sysid), compid_(compid) {}
  /// Appends one frame with msg to out.
  template <class T>
  void append(const T& msg, std::vector<std::uint8_t>& out) {
    append_as(msg, out, sysid_, compid_);
  }
  /// Appends one frame sent under other ids, on the same sequence counter (as the MAVLink C
  /// library does: one tx sequence per channel, mavlink_helpers.h mavlink_finalize_message_chan).
  template <class T>
  void append_as(const T& msg, std::vector<std::uint8_t>& out, std::uint8_t sysid, std::uint8_t compid) {
    const std::size_t at = out.size();
    out.resize(at + kHeaderLength + T::kLength + 2);
    encode(msg, seq_++, sysid, compid, out.data() + at);
  }
  template <class T>
  std::vector<std::uint8_t> frame(const T& msg) {
    std::vector<std::uint8_t> out;
    append(msg, out);
    return out;
  }

 private:
  std::uint8_t sysid_, compid_;
  std::uint8_t seq_ = 0;
};

}  // namespace tern::fcu::mavlink
