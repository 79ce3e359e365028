// core/apps/dds/src/answered_requests.hpp: a service's memory of the requests it has answered, so that
// a repeated request (a client retrying after a time-out) gets the first answer and is not
// applied twice (issue 20, item 5: a retried `mission add` added the waypoint twice).
//
// The id: tern's client puts a random 62-bit request id in the sequence-number half of the
// request's related_sample_identity. rmw_fastrtps reads only that field's writer GUID (the
// client's reply reader) and leaves the sequence number unknown (SequenceNumber_t::unknown(),
// high = -1), so a ROS 2 client's request carries no id here and is simply never deduplicated.
// Memory is bounded: the last kCapacity answers of each service.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <utility>

#include <fastdds/rtps/common/SampleIdentity.h>

namespace tern::core::ddsi {

/// The request id of a request's related_sample_identity, or nullopt (a ROS 2 client's request).
inline std::optional<std::uint64_t> request_id(const eprosima::fastrtps::rtps::SampleIdentity& related) {
  const auto& sn = related.sequence_number();
  if (sn.high < 0 || (sn.high == 0 && sn.low == 0)) return std::nullopt;
  return sn.to64long();
}

template <class Resp>
class AnsweredRequests {
 public:
  static constexpr std::size_t kCapacity = 256;

  /// The first answer to `id`, or nullptr.
  const Resp* find(std::uint64_t id) const {
    for (const auto& [i, r] : answers_)
      if (i == id) return &r;
    return nullptr;
  }
  /// Remembers the answer to `id`, forgetting the oldest beyond kCapacity.
  void remember(std::uint64_t id, const Resp& resp) {
    answers_.emplace_back(id, resp);
    if (answers_.size() > kCapacity) answers_.pop_front();
  }
  std::size_t size() const { return answers_.size(); }

 private:
  std::deque<std::pair<std::uint64_t, Resp>> answers_;
};

}  // namespace tern::core::ddsi
