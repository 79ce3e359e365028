// core/apps/dds/src/decoding_type.hpp: a fastddsgen type whose deserialize() refuses bytes it
// cannot decode instead of throwing (issue 78).
//
// Fast CDR 1.0 throws eprosima::fastcdr::exception::BadParamException for bytes no writer of the
// type produces: an encapsulation whose first byte is not 0, a CDR boolean other than 0 or 1. The
// code fastddsgen 2.3 generates catches only NotEnoughMemoryException, and Fast DDS 2.9's
// DataReader::take_next_sample does not catch either: the exception left a reader's listener on
// Fast DDS's receive thread, and one such sample from any participant on the domain ended the
// vehicle (std::terminate). Registered as Decoding<PubSubType>, the sample is refused as Fast DDS
// refuses a short one (deserialize() false: "Error deserializing data", the sample dropped).
#pragma once

#include <fastcdr/exceptions/Exception.h>
#include <fastrtps/rtps/common/SerializedPayload.h>

namespace tern::core::ddsi {

/// PubSub (a fastddsgen PubSubType) with the same type name, size and serialisation; deserialize()
/// false for bytes Fast CDR refuses.
template <class PubSub>
class Decoding final : public PubSub {
 public:
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    try {
      return PubSub::deserialize(payload, data);
    } catch (const eprosima::fastcdr::exception::Exception&) {
      return false;
    }
  }
};

}  // namespace tern::core::ddsi
