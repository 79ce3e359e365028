// core/formats/ros/cdr_writer.hpp: a ROS 2 message written field by field in CDR, as rmw
// implementations send it and rosbag2 stores it (XCDR1, plain CDR, little-endian): the 4-byte
// encapsulation header 00 01 00 00, then each primitive little-endian, aligned to its own size
// counted from the end of the header; a string is a uint32 length counting its terminating NUL,
// its bytes, then the NUL; a sequence (T[]) a uint32 element count, then its elements; a nested
// message is its fields in order. For the messages tern composes itself (scene_msgs.hpp);
// cdr_columns.hpp writes the flat log tables.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace tern::core {

class CdrWriter {
 public:
  /// Appends the encapsulation header to `out`; the fields follow it.
  explicit CdrWriter(std::string& out) : out_(out) {
    constexpr char kHeader[4] = {0x00, 0x01, 0x00, 0x00};  // CDR_LE, options 0
    out_.append(kHeader, sizeof kHeader);
    base_ = out_.size();
  }
  void f64(double v) { put(v); }
  void f32(float v) { put(v); }
  void i32(std::int32_t v) { put(v); }
  void u32(std::uint32_t v) { put(v); }
  void u8(std::uint8_t v) { put(v); }
  void boolean(bool v) { put(static_cast<std::uint8_t>(v ? 1 : 0)); }
  void string(std::string_view s) {
    put(static_cast<std::uint32_t>(s.size() + 1));
    out_.append(s);
    out_.push_back('\0');
  }
  /// A sequence's element count (its elements follow).
  void count(std::size_t n) { put(static_cast<std::uint32_t>(n)); }

 private:
  template <class T>
  void put(T v) {
    const std::size_t pos = out_.size() - base_;
    out_.resize(base_ + (pos + sizeof(T) - 1) / sizeof(T) * sizeof(T), '\0');
    char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));  // little-endian host (as cdr_columns.cpp)
    out_.append(bytes, sizeof(T));
  }
  std::string& out_;
  std::size_t base_ = 0;
};

}  // namespace tern::core
