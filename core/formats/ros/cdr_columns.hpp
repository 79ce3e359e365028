// core/formats/ros/cdr_columns.hpp: a logged message in ROS 2's wire encoding (CDR) and its
// `ros2msg` schema, from the message's flat log columns (tern/reflect.hpp layout()).
//
// The schema is tern_msgs/msg/<Name> (<Name>: the type name after "tern/"), one field per log
// column in column order, the column's unit as a comment:
//   float64 p_n  # m
// Field names follow ROS 2's rule (lower case, digits, single underscores: rosidl, and Foxglove's
// parser, refuse "Va"): the column's name in lower case ("va"), a repeat suffixed _2; the CSV
// header keeps the column's own name (the MCAP channel's tern.csv_header).
// The encoding is the one ROS 2's rmw implementations use (XCDR1, plain CDR): the 4-byte
// encapsulation header 00 01 00 00 (CDR, little-endian), then each field little-endian, aligned
// to its own size counted from the end of the header; bool is one byte 0/1. A message without
// columns gets the one field rosidl generates for a message without members,
// `uint8 structure_needs_at_least_one_member` (encoded as one zero byte).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "tern/reflect.hpp"

namespace tern::core {

/// "tern_msgs/msg/State" for "tern/State"; `fallback` (a topic name) when the type has no name.
std::string tern_schema_name(std::string_view type_name, std::string_view fallback);
/// A column's name as a ROS 2 field name (above).
std::string ros2msg_field_name(std::string_view column);
/// The ros2msg text of the columns (above).
std::string tern_schema_text(const std::vector<reflect::Column>& columns);
/// The ros2msg type of a scalar kind: "float64", "int32", "bool" ...
std::string_view ros2msg_type(reflect::Scalar kind);
/// The scalar kind of a ros2msg primitive type; nullopt for any other type.
std::optional<reflect::Scalar> scalar_of_ros2msg(std::string_view type);

/// The CDR encoding (above) of one message layout, worked out once: its size and the copies that
/// make it (columns adjacent in the message and in the encoding copied as one). The flight log
/// encodes every message of a topic with its topic's encoder.
class CdrEncoder {
 public:
  CdrEncoder() = default;  ///< for a message without columns, as CdrEncoder({})
  explicit CdrEncoder(const std::vector<reflect::Column>& columns);
  /// Bytes of every message's encoding, header included.
  std::size_t size() const { return size_; }
  /// Appends the encoding of the message at `msg` (the columns' layout) to `out`.
  void append(const char* msg, std::string& out) const;

 private:
  struct Run {
    std::size_t from, to, n;  // bytes at msg + from go to encoding + to
  };
  std::vector<Run> runs_;
  std::vector<std::pair<std::size_t, std::size_t>> bools_;  // (from, to): one byte 0/1 each
  std::size_t size_ = 5;                                    // the header and the empty message's one byte
};

/// Appends the CDR encoding (header included) of the message at `msg` to `out` (CdrEncoder, once).
void encode_cdr(const std::vector<reflect::Column>& columns, const char* msg, std::string& out);
/// Decodes `data` (CDR, header included) into the message at `msg` (columns' offsets); false if
/// the header is not little-endian CDR or the data ends early.
bool decode_cdr(const std::vector<reflect::Column>& columns, std::string_view data, char* msg);

}  // namespace tern::core
