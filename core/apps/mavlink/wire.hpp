// core/apps/mavlink/wire.hpp: little-endian reads and writes of a MAVLink payload's fields, at the
// offsets of its wire layout (fields in the order mavlink_messages.hpp states: sorted by type size,
// extensions last). Used by the message encoders and decoders (mavlink_messages.cpp,
// mission_messages.cpp).
//
// Errors: none thrown. Writer needs a message id that message_info() knows; Reader reads zeros
// past the payload's end.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "mavlink/mavlink_codec.hpp"

namespace tern::core::mavlink {

/// Little-endian writes into a payload of the message's full length.
class Writer {
 public:
  explicit Writer(std::uint32_t msgid) : p_(message_info(msgid)->length, 0) {}
  template <class T>
  Writer& put(T v) {
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));  // tern builds for little-endian hosts only (x86-64, aarch64)
    std::copy(b, b + sizeof(T), p_.begin() + static_cast<std::ptrdiff_t>(at_));
    at_ += sizeof(T);
    return *this;
  }
  /// A char[n] field: the text, NUL-padded (no terminator when it fills the field).
  Writer& text(const std::string& s, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) p_[at_ + i] = i < s.size() ? static_cast<std::uint8_t>(s[i]) : 0;
    at_ += n;
    return *this;
  }
  std::vector<std::uint8_t> done() { return std::move(p_); }

 private:
  std::vector<std::uint8_t> p_;
  std::size_t at_ = 0;
};

class Reader {
 public:
  explicit Reader(const std::vector<std::uint8_t>& p) : p_(p) {}
  template <class T>
  T get() {
    T v{};
    if (at_ + sizeof(T) <= p_.size()) std::memcpy(&v, p_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  std::string text(std::size_t n) {
    std::string s;
    for (std::size_t i = 0; i < n && at_ + i < p_.size() && p_[at_ + i] != 0; ++i) s.push_back(static_cast<char>(p_[at_ + i]));
    at_ += n;
    return s;
  }

 private:
  const std::vector<std::uint8_t>& p_;
  std::size_t at_ = 0;
};

}  // namespace tern::core::mavlink
