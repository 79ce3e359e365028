// core/apps/dds/tests/test_wire_bytes.cpp (ctest dds_messages): the bytes on the wire, pinned.
// Every conversion of ddsi::all_types() (tern_msgs and the ROS types) and tern_msgs/MissionItem
// (to_mission_item) is run on three messages per struct: its defaults, every described field set
// as test_message_definitions.cpp sets it (epoch 0), and every field set to other values (epoch
// 1.7e18 ns); each sample's CDR bytes (hex) and `tern echo` text must equal
// wire_golden.txt's. The file was written before the tern_msgs IDL and conversions were generated
// from describe() (issue 60) and pins the wire they must keep. After a deliberate change of the
// wire, rewrite it with
//   TERN_WIRE_GOLDEN=write build/bin/tern_dds_message_tests -tc='*golden*'
// and say why in the commit.
#include <doctest/doctest.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "message_leaves.hpp"
#include "mission_item.hpp"
#include "tern_msgs/msg/VehiclePubSubTypes.h"
#include "wire_samples.hpp"

using namespace tern;
using namespace tern::dds_test;
namespace ddsi = tern::core::ddsi;

namespace {

constexpr Nanos kEpoch = 1'700'000'000'123'456'789;

/// A value for every leaf other than base_value's: signs, magnitudes and enumerations vary.
double varied_value(const Leaf& leaf, std::size_t i) {
  using reflect::Scalar;
  if (leaf.path == "count") return static_cast<double>(kItems);
  switch (leaf.kind) {
    case Scalar::f64:
    case Scalar::f32: return (i % 2 ? -37.125 : 1021.0625) * static_cast<double>(i + 1);
    case Scalar::i64: return 1'234'567'891'234.0 * static_cast<double>(i + 1);
    case Scalar::i8: return i % 2 ? -1.0 : 1.0;
    case Scalar::boolean: return static_cast<double>(i % 2);
    default: return static_cast<double>((i * 5 + 2) % 4);
  }
}

enum class Fill { defaults, base, varied };

template <class M>
M sample_message(Fill fill) {
  M m{};
  if (fill == Fill::defaults) return m;
  std::vector<Leaf> all;
  leaves<M>(all, "", "", 0);
  for (std::size_t i = 0; i < all.size(); ++i) assign(&m, all[i], fill == Fill::base ? base_value(all[i], i) : varied_value(all[i], i));
  return m;
}

constexpr std::pair<Fill, const char*> kFills[] = {{Fill::defaults, "defaults"}, {Fill::base, "base"}, {Fill::varied, "varied"}};

void put_sample(std::string& out, const WireSample& s, std::size_t index) {
  out += fmt::format("  sample {}\n", index);
  for (std::size_t i = 0; i < s.bytes.size(); i += 64) {
    out += "  cdr ";
    for (std::size_t j = i; j < s.bytes.size() && j < i + 64; ++j) out += fmt::format("{:02x}", s.bytes[j]);
    out += '\n';
  }
  std::istringstream lines(s.text);
  for (std::string line; std::getline(lines, line);) out += "  text " + line + '\n';
}

/// Every entry of all_types() on every fill (in the order of their names: the text does not
/// depend on the order of all_types()), then MissionItem.
std::string wire_text() {
  std::map<std::string, std::string> blocks;
  for (const auto& e : ddsi::all_types()) {
    with_message(e.tern_type, [&](auto* tag) {
      using M = std::remove_pointer_t<decltype(tag)>;
      std::string& out = blocks[fmt::format("{} -> {}", e.tern_type, e.dds_type)];
      for (const auto& [fill, name] : kFills) {
        out += fmt::format("{} -> {} ({})\n", e.tern_type, e.dds_type, name);
        const M m = sample_message<M>(fill);
        const auto samples = wire_samples(e, &m, fill == Fill::varied ? kEpoch : 0);
        for (std::size_t i = 0; i < samples.size(); ++i) put_sample(out, samples[i], i);
      }
    });
  }
  std::string out;
  for (const auto& [key, block] : blocks) out += block;
  tern_msgs::msg::MissionItemPubSubType type;
  for (const auto& [fill, name] : kFills) {
    tern_msgs::msg::MissionItem item;
    ddsi::to_mission_item(sample_message<msg::Waypoint>(fill), item);
    eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&item)());
    WireSample s;
    if (type.serialize(&item, &payload)) s.bytes.assign(payload.data, payload.data + payload.length);
    out += fmt::format("tern/Waypoint -> {} ({})\n", type.getName(), name);
    put_sample(out, s, 0);
  }
  return out;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The first line where the two texts differ, with its number.
std::string first_difference(const std::string& want, const std::string& have) {
  std::istringstream a(want), b(have);
  std::string la, lb;
  for (int n = 1;; ++n) {
    const bool ga = static_cast<bool>(std::getline(a, la)), gb = static_cast<bool>(std::getline(b, lb));
    if (!ga && !gb) return "";
    if (!ga || !gb || la != lb) return fmt::format("line {}:\n  golden: {}\n  now:    {}", n, ga ? la : "(end)", gb ? lb : "(end)");
  }
}

}  // namespace

TEST_CASE("dds messages: every conversion writes the golden wire bytes (wire_golden.txt)") {
  const std::string have = wire_text();
  const char* mode = std::getenv("TERN_WIRE_GOLDEN");
  if (mode != nullptr && std::string(mode) == "write") {
    std::ofstream(TERN_DDS_WIRE_GOLDEN) << have;
    MESSAGE("wrote ", TERN_DDS_WIRE_GOLDEN);
    return;
  }
  const std::string want = read_text(TERN_DDS_WIRE_GOLDEN);
  REQUIRE_MESSAGE(!want.empty(), "no ", TERN_DDS_WIRE_GOLDEN);
  CHECK_MESSAGE(want == have, first_difference(want, have));
}
