// codec.cpp: message-id lookup and typed decoding (see tern_fcu_serial/codec.hpp).
#include "tern_fcu_serial/codec.hpp"

namespace tern::fcu::mavlink {

namespace {
struct Table {
  std::array<const MessageInfo*, 256> by_id{};
  Table() {
    for (const MessageInfo& m : kDialect) by_id[m.id] = &m;
  }
};
const Table& table() {
  static const Table t;
  return t;
}

template <class T>
std::optional<Message> as(const Frame& f) {
  return Message(T::unpack(f.payload.data()));
}
}  // namespace

const MessageInfo* find_message(std::uint8_t id) { return table().by_id[id]; }

std::optional<Message> decode(const Frame& f) {
  const MessageInfo* info = find_message(f.msgid);
  if (info == nullptr || info->length != f.len) return std::nullopt;
  switch (f.msgid) {
    case SmallImu::kId: return as<SmallImu>(f);
    case SmallMag::kId: return as<SmallMag>(f);
    case SmallBaro::kId: return as<SmallBaro>(f);
    case DiffPressure::kId: return as<DiffPressure>(f);
    case RosflightGnss::kId: return as<RosflightGnss>(f);
    case RcChannels::kId: return as<RcChannels>(f);
    case RosflightStatus::kId: return as<RosflightStatus>(f);
    case AttitudeQuaternion::kId: return as<AttitudeQuaternion>(f);
    case RosflightOutputRaw::kId: return as<RosflightOutputRaw>(f);
    case ParamValue::kId: return as<ParamValue>(f);
    case RosflightCmdAck::kId: return as<RosflightCmdAck>(f);
    case RosflightVersion::kId: return as<RosflightVersion>(f);
    case Statustext::kId: return as<Statustext>(f);
    case Timesync::kId: return as<Timesync>(f);
    case Heartbeat::kId: return as<Heartbeat>(f);
    case OffboardControl::kId: return as<OffboardControl>(f);
    case ParamRequestList::kId: return as<ParamRequestList>(f);
    case ParamRequestRead::kId: return as<ParamRequestRead>(f);
    case ParamSet::kId: return as<ParamSet>(f);
    case RosflightCmd::kId: return as<RosflightCmd>(f);
    default: return std::nullopt;
  }
}

}  // namespace tern::fcu::mavlink
