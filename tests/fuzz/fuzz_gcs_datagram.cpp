// fuzz_gcs_datagram: libFuzzer target for the ground station's side of MAVLink 2 over UDP
// (core/apps/mavlink): one datagram's frames (mavlink_codec.hpp parse_datagram, on the SDK's framing
// and checksum), every frame decoded as the generated message of its id and packed back, and the
// decoded messages fed to what the link does with them without a host or a socket: the mission
// upload's checks (mission_items.hpp: check_item per MISSION_ITEM_INT, to_mission of the accepted
// ones, the waypoint file mission_text writes read back by the planner's parse_mission_text, as
// MissionProtocol::finish_upload does) and PARAM_SET / PARAM_REQUEST_READ's ids and values
// (param_ids.hpp).
//
// The input is read twice: as one datagram (any bytes), and as records [message][length][payload]
// wrapped into a datagram of well-formed frames (right CRC_EXTRA and checksum), so that random
// payloads reach the decoders and the mission checks. Never a crash, an out-of-bounds read, an
// exception other than ItemError / MissionError, or a frame lost or changed on the way.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "mavlink/mavlink_codec.hpp"
#include "mavlink/mission_items.hpp"
#include "mavlink/param_ids.hpp"

using namespace tern::core::mavlink;

namespace {

/// A decoded frame packed again gives back its payload (the generated unpack/pack agree).
template <class T>
bool repack(const Frame& f) {
  if (f.msgid != T::kId) return false;
  if (encode(decode<T>(f)) != f.payload) __builtin_trap();
  return true;
}

template <class... T>
void repack_any(const Frame& f) {
  (repack<T>(f) || ...);
}

const ParamTable& params() {
  // a mission's parameters as the link lists them: short ids, and long ones shortened
  static const ParamTable table({{"slc.roll_kp", tern::ParamKind::real},
                                 {"estimator_ekf.gyro_noise", tern::ParamKind::real},
                                 {"estimator_ekf.gps_delay_ms", tern::ParamKind::integer},
                                 {"path_manager.loop", tern::ParamKind::boolean}});
  return table;
}

void take(const std::vector<Frame>& frames) {
  const tern::GeoOrigin home(47.389, 8.034, 470.0);
  std::vector<MissionItemInt> upload;
  for (const Frame& f : frames) {
    const auto info = message_info(f.msgid);
    if (!info || f.payload.size() != info->length) __builtin_trap();
    repack_any<Heartbeat, ParamRequestRead, ParamRequestList, ParamSet, MissionRequest, MissionSetCurrent, MissionRequestList, MissionCount,
               MissionClearAll, MissionAck, MissionRequestInt, MissionItemInt, CommandInt, CommandLong, CommandAck, Timesync, Statustext>(
        f);
    if (f.msgid == MissionItemInt::kId) {
      MissionItemInt it = decode<MissionItemInt>(f);
      it.seq = static_cast<std::uint16_t>(upload.size());  // the protocol takes items in seq order only
      try {
        check_item(it);
        upload.push_back(it);
      } catch (const ItemError& e) {
        if (e.result() == MAV_MISSION_ACCEPTED || std::strchr(e.what(), '\n')) __builtin_trap();  // a refusal, one line
      }
    } else if (f.msgid == ParamSet::kId) {
      const auto m = decode<ParamSet>(f);
      if (const auto i = params().find(to_string(m.param_id))) (void)from_mav_value(m.param_value, params().params()[*i].kind);
      for (auto kind : {tern::ParamKind::real, tern::ParamKind::integer, tern::ParamKind::boolean})
        (void)from_mav_value(m.param_value, kind);
    } else if (f.msgid == ParamRequestRead::kId) {
      (void)params().find(to_string(decode<ParamRequestRead>(f).param_id));
    }
  }
  if (upload.empty()) return;
  try {
    std::vector<std::uint16_t> nav_seq;
    const tern::path::Mission m = to_mission(upload, home, &nav_seq);
    if (nav_seq.size() != m.waypoints.size()) __builtin_trap();
    if (m.waypoints.size() > tern::msg::WaypointList::kCapacity) return;  // refused by the protocol before it is written
    // the file written for the planner reads back to as many waypoints
    const std::string text = mission_text(m);
    if (tern::path::parse_mission_text(text, "MAVLink upload").waypoints.size() != m.waypoints.size()) __builtin_trap();
  } catch (const ItemError&) {
  } catch (const tern::path::MissionError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // 1. the bytes as they came
  Counters c;
  const std::vector<Frame> raw = parse_datagram(data, size, c);
  if (c.frames != raw.size() || c.datagrams != 1) __builtin_trap();
  take(raw);

  // 2. the bytes as well-formed frames: [message index][payload length][payload bytes]...
  std::vector<std::uint8_t> datagram;
  std::vector<std::vector<std::uint8_t>> sent;
  std::vector<std::uint32_t> ids;
  for (std::size_t i = 0; i + 2 <= size;) {
    const MessageInfo& info = kDialect[data[i] % kDialect.size()];
    const std::size_t len = std::min<std::size_t>({data[i + 1], info.length, size - i - 2});
    std::vector<std::uint8_t> payload(data + i + 2, data + i + 2 + len);
    payload.resize(info.length, 0);
    const auto frame = encode_frame(info.id, payload, static_cast<std::uint8_t>(sent.size()), 255, 190);
    datagram.insert(datagram.end(), frame.begin(), frame.end());
    sent.push_back(std::move(payload));
    ids.push_back(info.id);
    i += 2 + len;
  }
  if (sent.empty()) return 0;
  Counters w;
  const std::vector<Frame> frames = parse_datagram(datagram.data(), datagram.size(), w);
  if (frames.size() != sent.size() || w.dropped() != 0 || w.junk_bytes != 0) __builtin_trap();
  for (std::size_t k = 0; k < frames.size(); ++k)
    if (frames[k].msgid != ids[k] || frames[k].payload != sent[k] || frames[k].sysid != 255 || frames[k].compid != 190) __builtin_trap();
  take(frames);
  return 0;
}
