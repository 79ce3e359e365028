// core/apps/dds/src/matched_readers.hpp: the readers a service's reply writer has matched, so that a
// reply waits for the very reader that will take it. A reply is volatile: written before the
// writer has matched the asking client's reply reader, it is lost, and "some reader matched"
// (current_count > 0) is not enough when another client is connected. The client names its
// reader in the request's related_sample_identity (rmw_fastrtps convention).
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <set>

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/rtps/common/InstanceHandle.h>

namespace tern::core::ddsi {

class MatchedReaders final : public eprosima::fastdds::dds::DataWriterListener {
 public:
  using GUID = eprosima::fastrtps::rtps::GUID_t;
  void on_publication_matched(eprosima::fastdds::dds::DataWriter*, const eprosima::fastdds::dds::PublicationMatchedStatus& st) override {
    const GUID g = eprosima::fastrtps::rtps::iHandle2GUID(st.last_subscription_handle);
    std::lock_guard lk(mu_);
    if (st.current_count_change > 0) guids_.insert(g);
    if (st.current_count_change < 0) guids_.erase(g);
    cv_.notify_all();
  }
  /// Waits until `reader` has matched (GUID unknown: until any reader has). false on timeout.
  bool wait_for(const GUID& reader, std::chrono::milliseconds timeout) {
    std::unique_lock lk(mu_);
    return cv_.wait_for(lk, timeout, [&] { return reader == GUID::unknown() ? !guids_.empty() : guids_.count(reader) > 0; });
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  std::set<GUID> guids_;
};

}  // namespace tern::core::ddsi
