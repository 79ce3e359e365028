// core/apps/dds/tests/wire_samples.hpp: what one conversion of ddsi::all_types() puts on the
// wire for one tern message: each sample it writes (a waypoint list on waypoint_path writes
// several), as Fast DDS serializes it (CDR with its 4-byte encapsulation header), and as
// `tern echo` renders it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <fastdds/rtps/common/SerializedPayload.h>

#include "dds_internal.hpp"

namespace tern::dds_test {

struct WireSample {
  std::vector<unsigned char> bytes;  ///< the serialized payload
  std::string text;                  ///< TypeEntry::render of the sample
};

/// Every sample entry `e` writes for the tern message at `m`, stamps offset by `epoch` (ns).
inline std::vector<WireSample> wire_samples(const core::ddsi::TypeEntry& e, const void* m, Nanos epoch) {
  std::unique_ptr<core::ddsi::fdds::TopicDataType> type(e.make_type());
  auto sample = e.make_sample();
  std::vector<WireSample> out;
  e.convert(m, sample.get(), epoch, [&] {
    eprosima::fastrtps::rtps::SerializedPayload_t payload(type->getSerializedSizeProvider(sample.get())());
    WireSample s;
    if (type->serialize(sample.get(), &payload)) s.bytes.assign(payload.data, payload.data + payload.length);
    s.text = e.render(sample.get());
    out.push_back(std::move(s));
  });
  return out;
}

}  // namespace tern::dds_test
