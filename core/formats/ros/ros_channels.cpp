#include "ros/ros_channels.hpp"

namespace tern::core {
namespace {
RosChannelLookup& lookup_slot() {
  static RosChannelLookup lookup;
  return lookup;
}
}  // namespace

void set_ros_channel_lookup(RosChannelLookup lookup) { lookup_slot() = std::move(lookup); }
const RosChannelLookup& ros_channel_lookup() { return lookup_slot(); }

}  // namespace tern::core
