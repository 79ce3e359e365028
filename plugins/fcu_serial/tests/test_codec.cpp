// MAVLink codec: CRC_EXTRA values, round trips of every message, the parser on corrupted streams.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <random>

#include "tern_fcu_serial/codec.hpp"

using namespace tern::fcu::mavlink;

namespace {
std::vector<Frame> parse_all(Parser& p, const std::vector<std::uint8_t>& bytes) {
  std::vector<Frame> out;
  p.feed(bytes.data(), bytes.size(), [&](const Frame& f) { out.push_back(f); });
  return out;
}

template <class T>
T round_trip(const T& in) {
  Encoder enc(1, 1);
  const auto bytes = enc.frame(in);
  REQUIRE(bytes.size() == kHeaderLength + T::kLength + 2);
  Parser p;
  const auto frames = parse_all(p, bytes);
  REQUIRE(frames.size() == 1);
  const auto m = decode(frames[0]);
  REQUIRE(m.has_value());
  REQUIRE(std::holds_alternative<T>(*m));
  return std::get<T>(*m);
}

bool same_bytes(const auto& a, const auto& b) {
  std::array<std::uint8_t, 255> x{}, y{};
  a.pack(x.data());
  b.pack(y.data());
  return x == y;
}

template <class T>
void check_round_trip(const T& in) {
  CAPTURE(T::kName);
  const T out = round_trip(in);
  CHECK(same_bytes(in, out));
}
}  // namespace

TEST_CASE("CRC_EXTRA and lengths match MAVLink's published values") {
  // common.xml messages (published by the MAVLink project) and ROSflight's generated headers.
  struct Want {
    std::uint8_t id, len, crc;
  };
  const Want want[] = {{0, 9, 50},    {20, 20, 214}, {21, 2, 159},  {22, 25, 220}, {23, 23, 168}, {31, 32, 246},
                       {65, 42, 118}, {111, 16, 34}, {253, 51, 83}, {181, 36, 67}, {197, 66, 221}};
  for (const Want& w : want) {
    CAPTURE(int(w.id));
    const MessageInfo* m = find_message(w.id);
    REQUIRE(m != nullptr);
    CHECK(int(m->length) == int(w.len));
    CHECK(int(m->crc_extra) == int(w.crc));
  }
  CHECK(Heartbeat::kCrcExtra == 50);
  CHECK(find_message(1) == nullptr);
  CHECK(kDialect.size() == 25);
}

TEST_CASE("X.25 checksum: the CRC-16/MCRF4XX check value") {
  const char* s = "123456789";
  CHECK(crc_calculate(reinterpret_cast<const std::uint8_t*>(s), 9) == 0x6F91);
}

TEST_CASE("a HEARTBEAT frame is byte-exact") {
  Heartbeat h;
  h.type = 1;
  h.autopilot = 12;
  h.base_mode = 0x80;
  h.custom_mode = 0x01020304;
  h.system_status = 4;
  h.mavlink_version = 3;
  std::uint8_t out[32];
  const std::size_t n = encode(h, 7, 1, 250, out);
  REQUIRE(n == 17);
  // wire order: custom_mode (uint32) first, then the uint8 fields in definition order
  const std::uint8_t head[] = {0xFE, 9, 7, 1, 250, 0, 0x04, 0x03, 0x02, 0x01, 1, 12, 0x80, 4, 3};
  CHECK(std::equal(std::begin(head), std::end(head), out));
  std::uint16_t crc = crc_calculate(out + 1, 14);
  crc = crc_accumulate(50, crc);
  CHECK(out[15] == (crc & 0xFF));
  CHECK(out[16] == (crc >> 8));
}

TEST_CASE("every message survives encode -> parse -> decode") {
  SmallImu imu;
  imu.time_boot_us = 123456789012ull;
  imu.xacc = 0.1f;
  imu.yacc = -0.2f;
  imu.zacc = -9.81f;
  imu.xgyro = 0.01f;
  imu.ygyro = -0.02f;
  imu.zgyro = 0.03f;
  imu.temperature = 301.5f;
  check_round_trip(imu);
  CHECK(round_trip(imu).time_boot_us == 123456789012ull);
  CHECK(round_trip(imu).zacc == -9.81f);
  SmallMag mag;
  mag.xmag = 2e-5f;
  mag.ymag = -3e-6f;
  mag.zmag = 4.5e-5f;
  check_round_trip(mag);
  SmallBaro baro;
  baro.altitude = 1387.f;
  baro.pressure = 85000.5f;
  baro.temperature = 290.f;
  check_round_trip(baro);
  DiffPressure dp;
  dp.velocity = 17.f;
  dp.diff_pressure = 180.2f;
  dp.temperature = 289.f;
  check_round_trip(dp);
  RosflightGnss g;
  g.seconds = 1700000000;
  g.nanos = 123456789;
  g.fix_type = 3;
  g.num_sat = 12;
  g.lat = 40.2463724;
  g.lon = -111.6474138;
  g.height = 1400.5f;
  g.vel_n = 10.f;
  g.vel_e = -2.f;
  g.vel_d = 0.5f;
  g.h_acc = 0.6f;
  g.v_acc = 1.2f;
  g.s_acc = 0.01f;
  g.rosflight_timestamp = 987654321ull;
  check_round_trip(g);
  CHECK(round_trip(g).lat == 40.2463724);
  RcChannels rc;
  rc.time_boot_ms = 42;
  rc.chancount = 8;
  rc.chan1_raw = 1100;
  rc.chan2_raw = 1900;
  rc.chan3_raw = 1000;
  rc.chan4_raw = 1500;
  rc.chan18_raw = 0xFFFF;
  rc.rssi = 255;
  check_round_trip(rc);
  RosflightStatus st;
  st.armed = 1;
  st.failsafe = 0;
  st.rc_override = 3;
  st.offboard = 1;
  st.error_code = 4;
  st.control_mode = 0;
  st.num_errors = -2;
  st.loop_time_us = 250;
  check_round_trip(st);
  AttitudeQuaternion q;
  q.time_boot_ms = 99;
  q.q1 = 1;
  q.q2 = 0.1f;
  q.q3 = -0.2f;
  q.q4 = 0.3f;
  q.rollspeed = 0.5f;
  q.pitchspeed = -0.5f;
  q.yawspeed = 0.25f;
  check_round_trip(q);
  RosflightOutputRaw o;
  o.stamp = 55;
  for (int i = 0; i < 14; ++i) o.values[i] = 0.1f * i;
  check_round_trip(o);
  ParamValue pv;
  pv.param_id = to_chars<16>("RC_ATT_OVRD_CHN");
  pv.param_value = 5.f;
  pv.param_type = 9;
  pv.param_count = 200;
  pv.param_index = 17;
  check_round_trip(pv);
  CHECK(to_string(round_trip(pv).param_id) == "RC_ATT_OVRD_CHN");
  RosflightCmdAck ack;
  ack.command = 6;
  ack.success = 1;
  check_round_trip(ack);
  RosflightVersion v;
  v.version = to_chars<50>("v2.0.0-tern-emulator");
  check_round_trip(v);
  Statustext t;
  t.severity = 4;
  t.text = to_chars<50>("RC lost: failsafe");
  check_round_trip(t);
  Timesync ts;
  ts.tc1 = -5;
  ts.ts1 = 1234567890123456789ll;
  check_round_trip(ts);
  Heartbeat hb;
  hb.type = 1;
  hb.custom_mode = 77;
  hb.mavlink_version = 3;
  check_round_trip(hb);
  OffboardControl oc;
  oc.mode = 0;
  oc.ignore = 0x3F0;
  oc.u = {0.5f, -0.25f, 0.1f, 0.75f};
  check_round_trip(oc);
  CHECK(round_trip(oc).ignore == 0x3F0);
  ParamRequestList prl;
  prl.target_system = 1;
  prl.target_component = 1;
  check_round_trip(prl);
  ParamRequestRead prr;
  prr.target_system = 1;
  prr.param_id = to_chars<16>("BAUD_RATE");
  prr.param_index = -1;
  check_round_trip(prr);
  ParamSet ps;
  ps.param_id = to_chars<16>("ABCDEFGHIJKLMNOP");
  ps.param_value = 1.5f;
  ps.param_type = 9;
  check_round_trip(ps);
  CHECK(to_string(round_trip(ps).param_id) == "ABCDEFGHIJKLMNOP");  // 16 characters, no NUL
  RosflightCmd cmd;
  cmd.command = 8;
  check_round_trip(cmd);
}

TEST_CASE("parser: bad CRC, unknown id, wrong length and garbage are counted, valid frames kept") {
  Encoder enc(1, 1);
  Timesync ts;
  ts.tc1 = 1;
  ts.ts1 = 2;
  std::vector<std::uint8_t> stream;
  auto add = [&](const std::vector<std::uint8_t>& bytes) {
    for (std::uint8_t b : bytes) stream.push_back(b);
  };
  add({0x00, 0x11, 0x22});  // garbage
  auto bad = enc.frame(ts);
  bad[10] ^= 0x40;  // payload bit flip -> CRC fails
  add(bad);
  add({0xFE, 3, 0, 1, 1, 77, 0, 0, 0, 0, 0});         // id 77 is not in the dialect
  add({0xFE, 5, 0, 1, 1, 111, 1, 2, 3, 4, 5, 0, 0});  // TIMESYNC with 5 bytes
  const auto good = enc.frame(ts);
  add(good);
  Parser p;
  const auto frames = parse_all(p, stream);
  REQUIRE(frames.size() == 1);
  CHECK(frames[0].msgid == Timesync::kId);
  CHECK(frames[0].seq == 1);
  CHECK(p.stats().bad_crc == 1);
  CHECK(p.stats().unknown_id == 1);
  CHECK(p.stats().bad_length == 1);
  CHECK(p.stats().frames == 1);
  CHECK(p.stats().skipped + good.size() == stream.size());
}

TEST_CASE("parser: a truncated frame does not swallow the frame after it") {
  Encoder enc(1, 1);
  SmallImu imu;
  imu.time_boot_us = 5;
  const auto a = enc.frame(imu);
  const auto b = enc.frame(imu);
  std::vector<std::uint8_t> stream(a.begin(), a.begin() + 20);  // cut in the payload
  stream.insert(stream.end(), b.begin(), b.end());
  Parser p;
  const auto frames = parse_all(p, stream);
  REQUIRE(frames.size() == 1);
  CHECK(frames[0].seq == 1);
  CHECK(p.stats().bad_crc + p.stats().bad_length + p.stats().unknown_id >= 1);
}

TEST_CASE("parser: fed one byte at a time or in bursts, the same frames come out") {
  Encoder enc(1, 1);
  std::vector<std::uint8_t> stream;
  for (int i = 0; i < 50; ++i) {
    SmallImu imu;
    imu.time_boot_us = static_cast<std::uint64_t>(i);
    enc.append(imu, stream);
    SmallBaro b;
    b.pressure = static_cast<float>(i);
    enc.append(b, stream);
  }
  Parser whole, bytewise;
  const auto f1 = parse_all(whole, stream);
  std::vector<Frame> f2;
  for (std::uint8_t b : stream) bytewise.feed(&b, 1, [&](const Frame& f) { f2.push_back(f); });
  REQUIRE(f1.size() == 100);
  REQUIRE(f2.size() == 100);
  for (std::size_t i = 0; i < f1.size(); ++i) CHECK(std::memcmp(&f1[i], &f2[i], sizeof(Frame)) == 0);
  CHECK(whole.stats().skipped == 0);
  CHECK(whole.stats().seq_gaps == 0);
}

TEST_CASE("parser: randomized corruption never loses an untouched frame and never crashes") {
  std::mt19937_64 rng(20261121);
  std::uniform_int_distribution<int> byte(0, 255), kind(0, 5), pick(0, 3);
  Encoder enc(1, 1);
  std::uint64_t intact = 0;
  std::vector<std::uint8_t> stream;
  std::vector<std::uint64_t> expected;  // time_boot_us of the untouched IMU frames, in order
  for (int i = 0; i < 4000; ++i) {
    SmallImu imu;
    imu.time_boot_us = static_cast<std::uint64_t>(i) + 1;
    imu.xacc = static_cast<float>(i);
    auto f = enc.frame(imu);
    switch (kind(rng)) {
      case 0:
        f[std::uniform_int_distribution<std::size_t>(0, f.size() - 1)(rng)] ^=
            static_cast<std::uint8_t>(1 + byte(rng) % 255);  // corrupt one byte
        break;
      case 1: f.resize(std::uniform_int_distribution<std::size_t>(1, f.size() - 1)(rng)); break;  // truncate
      case 2: {  // garbage before the frame, with start bytes in it
        std::vector<std::uint8_t> g(static_cast<std::size_t>(byte(rng) % 40));
        for (auto& x : g) x = pick(rng) == 0 ? kStx : static_cast<std::uint8_t>(byte(rng));
        stream.insert(stream.end(), g.begin(), g.end());
        [[fallthrough]];
      }
      default:
        expected.push_back(imu.time_boot_us);
        ++intact;
        break;
    }
    stream.insert(stream.end(), f.begin(), f.end());
  }
  Parser p;
  std::vector<std::uint64_t> got;
  // feed in random-sized bursts
  std::size_t at = 0;
  while (at < stream.size()) {
    const std::size_t n = std::min<std::size_t>(stream.size() - at, 1 + static_cast<std::size_t>(byte(rng)) * 4);
    p.feed(stream.data() + at, n, [&](const Frame& f) {
      const auto m = decode(f);
      REQUIRE(m.has_value());
      REQUIRE(std::holds_alternative<SmallImu>(*m));
      got.push_back(std::get<SmallImu>(*m).time_boot_us);
    });
    at += n;
  }
  // Every untouched frame is delivered; a corrupted frame is delivered only if the corruption
  // hit a byte the checksum does not cover (the start byte is resynchronised on the next one).
  CHECK(got == expected);
  CHECK(got.size() == intact);
  CHECK(p.stats().bytes == stream.size());
  CHECK(p.stats().bad_crc + p.stats().bad_length + p.stats().unknown_id > 0);
  CHECK(p.stats().skipped > 0);
  // after the stream, a clean frame still parses
  SmallImu last;
  last.time_boot_us = 999999;
  const auto f = enc.frame(last);
  std::size_t n = 0;
  p.feed(f.data(), f.size(), [&](const Frame&) { ++n; });
  // the previous stream may end with a partial frame that this one completes wrongly: at most
  // one more frame later everything is in sync again
  const auto f2 = enc.frame(last);
  p.feed(f2.data(), f2.size(), [&](const Frame&) { ++n; });
  CHECK(n >= 1);
}
