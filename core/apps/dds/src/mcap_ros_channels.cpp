// core/apps/dds/src/mcap_ros_channels.cpp: the MCAP log's ROS-typed channels (core/formats/ros/ros_channels.hpp),
// from the bridge's own conversions: the topics, names and types of ROSplane's profile
// (rosplane_profile.cpp), the tern -> ROS conversion of each (convert.cpp) and Fast DDS's CDR
// serialisation of the generated type, with the encapsulation header, as rosbag2 stores it.
#include <deque>
#include <map>
#include <memory>
#include <set>

#include <fastdds/rtps/common/SerializedPayload.h>

#include "dds_bridge.hpp"
#include "dds_internal.hpp"
#include "ros/ros_channels.hpp"

namespace tern::core {

const std::map<std::string, std::string>& ros_msg_texts();  // generated (core/apps/dds/CMakeLists.txt)

namespace {

/// "pkg/Type" or "pkg/msg/Type" -> "pkg/msg/Type"
std::string full_name(const std::string& type) {
  const auto slash = type.find('/');
  return type.find("/msg/") == std::string::npos && slash != std::string::npos ? type.substr(0, slash) + "/msg" + type.substr(slash) : type;
}

/// The complex field types ("pkg/Type") a .msg text uses, in order of appearance.
std::vector<std::string> used_types(const std::string& text) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    const std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    std::string type = line.substr(first, line.find_first_of(" \t", first) - first);
    if (const auto bracket = type.find('['); bracket != std::string::npos) type.resize(bracket);
    if (type.find('/') != std::string::npos) out.push_back(type);
  }
  return out;
}

/// The ros2msg schema of `type` ("rosplane_msgs/msg/State"): its .msg text, then each type it
/// uses (in order of first use, once) after a line of 80 '=' and "MSG: pkg/Type", as rosbag2
/// writes it. Empty when a text is missing.
std::string ros2msg_schema(const std::string& type) {
  const auto& texts = ros_msg_texts();
  const auto root = texts.find(type);
  if (root == texts.end()) return {};
  std::string out = root->second;
  std::set<std::string> done{type};
  const std::vector<std::string> direct = used_types(root->second);
  std::deque<std::string> queue(direct.begin(), direct.end());  // breadth first: each type once
  while (!queue.empty()) {
    const std::string dep = queue.front();
    queue.pop_front();
    const std::string name = full_name(dep);
    if (!done.insert(name).second) continue;
    const auto it = texts.find(name);
    if (it == texts.end()) return {};
    const std::string short_name = name.substr(0, name.find('/')) + name.substr(name.rfind('/'));
    out += "\n" + std::string(80, '=') + "\nMSG: " + short_name + "\n" + it->second;
    for (auto& d : used_types(it->second)) queue.push_back(d);
  }
  return out;
}

}  // namespace

void register_dds_mcap_channels() {
  set_ros_channel_lookup([](std::string_view topic, std::string_view type_name) -> std::optional<RosChannel> {
    for (const DdsTopicOptions& t : DdsOptions::rosplane_profile(false)) {
      if (t.topic != topic || t.type.empty()) continue;
      const ddsi::TypeEntry* e = ddsi::find_type(type_name, t.type);
      if (e == nullptr) return std::nullopt;
      RosChannel c;
      // as the bridge names it on the wire with the default namespace: /tern/estimated_state (beside
      // tern's own channel /state; /gnss, /baro ... would otherwise carry two types)
      const std::string ns = DdsOptions{}.ns;
      c.topic = ns.empty() ? "/" + t.name : "/" + ns + "/" + t.name;
      c.type = e->ros_type;
      c.schema = ros2msg_schema(e->ros_type);
      if (c.schema.empty()) return std::nullopt;
      std::shared_ptr<eprosima::fastdds::dds::TopicDataType> type(e->make_type());
      std::shared_ptr<void> sample = e->make_sample();
      // header stamps in flight time (the log's time; the bridge's epoch 0, as in simulation)
      c.encode = [e, type, sample](const void* msg, std::vector<std::string>& out) {
        e->convert(msg, sample.get(), 0, [&] {
          eprosima::fastrtps::rtps::SerializedPayload_t payload(type->getSerializedSizeProvider(sample.get())());
          if (type->serialize(sample.get(), &payload)) out.emplace_back(reinterpret_cast<const char*>(payload.data), payload.length);
        });
      };
      return c;
    }
    return std::nullopt;
  });
}

}  // namespace tern::core
