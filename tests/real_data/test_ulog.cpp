// The ULog reader against PX4's sample logs and pyulog's printouts of them
// (../shared/reference/ulog_samples: sample_info.txt, sample_messages.txt, sample_log_small_messages.txt;
// tests/real_data/ulog: pyulog's appended-data and tagged-logging samples), and corrupt or cut copies of them.
// The cases on ../shared/reference's samples are skipped when that folder is absent (a clone
// without ../shared): the case "ulog samples: ..." prints which.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <unistd.h>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "../test_process.hpp"
#include "import/importers.hpp"
#include "import/ulog_import.hpp"
#include "import/ulog_reader.hpp"
#include "tern/math.hpp"

namespace fs = std::filesystem;
using tern::core::ulog::DataHandler;
using tern::core::ulog::DataMessage;
using tern::core::ulog::LoggedString;
using tern::core::ulog::Reader;
using tern::core::ulog::Subscription;
using tern::core::ulog::UlogDataStats;
using tern::core::ulog::UlogError;

namespace {

const fs::path kSamples = fs::path(TERN_REFERENCE_DIR) / "ulog_samples";
/// doctest decorator of a case that reads kSamples: skipped without them (outside the repository).
const auto kNeedsSamples = doctest::skip(!fs::exists(kSamples / "sample.ulg") || !fs::exists(kSamples / "sample_log_small.ulg"));

std::vector<std::string> lines_of(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

/// pyulog's `messages` line: "h:mm:ss LEVEL: text" (the printouts' pyulog version has no milliseconds).
std::string pyulog_message_line(const LoggedString& s) {
  const std::uint64_t sec = s.timestamp / 1000000;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%d:%02d:%02d", static_cast<int>(sec / 3600), static_cast<int>(sec / 60 % 60), static_cast<int>(sec % 60));
  return std::string(buf) + " " + std::string(s.level_name()) + ": " + s.message;
}

struct Topic {
  std::size_t size = 0;
  std::uint64_t count = 0;
};

/// Everything the tests check, collected in one streaming pass.
struct Collected {
  std::map<std::string, Topic> topics;  // "name (multi_id, size)" as pyulog prints it
  std::vector<std::string> messages;
  std::vector<std::uint16_t> dropouts;
  std::vector<std::map<std::string, double>> rows;  // first rows of `row_topic`, by field name
  std::string row_topic;
  UlogDataStats stats;
};

Collected collect(Reader& r, const std::string& row_topic = "", std::size_t max_rows = 3) {
  Collected c;
  c.row_topic = row_topic;
  DataHandler h;
  h.on_data = [&](const DataMessage& d) {
    const Subscription& s = d.subscription();
    auto& t = c.topics[s.name + " (" + std::to_string(s.multi_id) + ", " + std::to_string(s.size()) + ")"];
    ++t.count;
    if (s.name == c.row_topic && c.rows.size() < max_rows) {
      auto& row = c.rows.emplace_back();
      for (const auto& f : s.fields()) row[f.name] = d.value(f);
    }
  };
  h.on_logged_string = [&](const LoggedString& s) { c.messages.push_back(pyulog_message_line(s)); };
  h.on_dropout = [&](std::uint16_t ms, std::uint64_t) { c.dropouts.push_back(ms); };
  c.stats = r.read_data(h);
  return c;
}

/// pyulog info's table, " name (multi id, size)   count   total bytes", by "name (multi id, size)".
std::map<std::string, Topic> pyulog_info_table(const fs::path& info) {
  std::map<std::string, Topic> table;
  bool in_table = false;
  for (const auto& line : lines_of(info)) {
    if (line.rfind("Name (multi id", 0) == 0) {
      in_table = true;
      continue;
    }
    if (!in_table) continue;
    const auto close = line.find(')');
    std::istringstream rest(line.substr(close + 1));
    std::uint64_t count = 0, bytes = 0;
    rest >> count >> bytes;
    table[line.substr(1, close)] = {static_cast<std::size_t>(bytes / count), count};
  }
  return table;
}

/// The reader saw exactly pyulog's topics, each with pyulog's count.
void check_topics(const Collected& c, const std::map<std::string, Topic>& expected) {
  CHECK(c.topics.size() == expected.size());
  for (const auto& [key, t] : expected) {
    INFO(key);
    REQUIRE(c.topics.count(key) == 1);
    CHECK(c.topics.at(key).count == t.count);
  }
}

fs::path scratch_copy(const std::string& name, const std::string& bytes) {
  const fs::path p = fs::temp_directory_path() / ("tern_test_ulog_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return p;
}

std::string file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The UlogError's text, or "" if none is thrown.
std::string error_reading(const fs::path& p) {
  try {
    Reader r(p);
    collect(r);
  } catch (const UlogError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("ulog samples: PX4's sample.ulg and sample_log_small.ulg from ../shared/reference, or the cases on them skipped") {
  if (fs::exists(kSamples / "sample.ulg") && fs::exists(kSamples / "sample_log_small.ulg")) return;
  std::printf(
      "test_ulog: %s has no sample.ulg or sample_log_small.ulg (PX4/pyulog's test/ files, outside the repository): the 9 cases "
      "on them are skipped\n",
      kSamples.c_str());
}

TEST_CASE("ulog reader: sample.ulg's info, topics and counts are pyulog's (sample_info.txt)" * kNeedsSamples) {
  Reader r(kSamples / "sample.ulg");
  CHECK(r.version() == 0);  // a 2017 log: file version 0, no flag bits message
  CHECK(r.initial_parameters().size() == 493);
  CHECK(r.info().at("sys_name").text() == "PX4");
  CHECK(r.info().at("ver_hw").text() == "AUAV_X21");
  CHECK(r.info().at("ver_sw").text() == "fd483321a5cf50ead91164356d15aa474643aa73");
  CHECK(r.info().at("time_ref_utc").text() == "0");
  const Collected c = collect(r);

  // "Logging start time: 0:01:52, duration: 0:01:08"
  CHECK(r.start_timestamp() / 1000000 == 1 * 60 + 52);
  CHECK((c.stats.last_timestamp - r.start_timestamp()) / 1000000 == 1 * 60 + 8);
  // "Dropouts: count: 4, total duration: 0.1 s, max: 62 ms, mean: 29 ms"
  REQUIRE(c.dropouts.size() == 4);
  unsigned total = 0, max = 0;
  for (auto d : c.dropouts) total += d, max = std::max<unsigned>(max, d);
  CHECK(max == 62);
  CHECK(total / 4 == 29);
  CHECK(std::round(total / 100.0) / 10.0 == doctest::Approx(0.1));

  const std::map<std::string, Topic> expected = pyulog_info_table(kSamples / "sample_info.txt");
  REQUIRE(expected.size() == 15);
  check_topics(c, expected);
  CHECK(c.stats.truncated == 0);
  CHECK(c.stats.unknown_msg_id == 0);
  CHECK(c.stats.wrong_size == 0);
  CHECK(c.stats.corrupt_regions == 0);
}

TEST_CASE("ulog reader: logged strings are pyulog's (sample_messages.txt, sample_log_small_messages.txt)" * kNeedsSamples) {
  for (const char* name : {"sample", "sample_log_small"}) {
    INFO(name);
    Reader r(kSamples / (std::string(name) + ".ulg"));
    const Collected c = collect(r);
    CHECK(c.messages == lines_of(kSamples / (std::string(name) + "_messages.txt")));
    CHECK(c.stats.truncated == 0);
  }
}

TEST_CASE("ulog reader: pyulog's appended-data and tagged-logging samples (tests/real_data/ulog)") {
  const fs::path dir = fs::path(TERN_SOURCE_DIR) / "tests" / "real_data" / "ulog";
  SUBCASE("sample_appended_multiple.ulg: data appended twice after the log ended (flag bits' appended offsets)") {
    Reader r(dir / "sample_appended_multiple.ulg");
    CHECK(r.version() == 1);
    const Collected c = collect(r);
    // "Logging start time: 0:00:12, duration: 0:00:09", "No Dropouts"
    CHECK(r.start_timestamp() / 1000000 == 12);
    CHECK((c.stats.last_timestamp - r.start_timestamp()) / 1000000 == 9);
    CHECK(c.dropouts.empty());
    const std::map<std::string, Topic> expected = pyulog_info_table(dir / "sample_appended_multiple_info.txt");
    REQUIRE(expected.size() == 20);
    check_topics(c, expected);
    CHECK(c.messages == lines_of(dir / "sample_appended_multiple_messages.txt"));
    CHECK(c.stats.truncated == 0);
    CHECK(c.stats.unknown_msg_id == 0);
    CHECK(c.stats.corrupt_regions == 0);
  }
  SUBCASE("sample_logging_tagged_and_default_params.ulg: tagged logged strings, parameter defaults") {
    Reader r(dir / "sample_logging_tagged_and_default_params.ulg");
    std::vector<std::string> untagged;
    std::vector<LoggedString> tagged;
    DataHandler h;
    h.on_logged_string = [&](const LoggedString& s) {
      // pyulog's `messages` prints the untagged strings ('L') and skips one ending in a tab: the
      // copy of a PX4 event, which it prints decoded from the `event` topic with PX4's event
      // metadata instead (its line 2, "logging: opening log file ..."; this reader has no such
      // metadata). Tagged strings ('C') are pyulog's logged_messages_tagged, not printed.
      if (s.tag)
        tagged.push_back(s);
      else if (s.message.empty() || s.message.back() != '\t')
        untagged.push_back(pyulog_message_line(s));
    };
    const UlogDataStats stats = r.read_data(h);
    std::vector<std::string> expected = lines_of(dir / "sample_logging_tagged_and_default_params_messages.txt");
    REQUIRE(expected.size() == 4);
    CHECK(expected[1] == "0:00:00 INFO: logging: opening log file 2022-4-29/8_45_27.ulg");
    expected.erase(expected.begin() + 1);
    CHECK(untagged == expected);
    REQUIRE(tagged.size() == 3);
    for (const auto& t : tagged) {
      CHECK(*t.tag == 1);
      CHECK(t.level_name() == "INFO");
      CHECK(t.message == "tagged message test");
    }
    // 'Q' default parameters by default type bit, as a struct.unpack of the spec's layout counts them
    REQUIRE(r.default_parameters().count(0) == 1);
    REQUIRE(r.default_parameters().count(1) == 1);
    CHECK(r.default_parameters().at(0).size() == 44);  // system defaults
    CHECK(r.default_parameters().at(1).size() == 21);  // the current setup's defaults
    CHECK(r.default_parameters().at(0).at("BAT1_N_CELLS").type == "int32_t");
    CHECK(r.default_parameters().at(0).at("BAT1_N_CELLS").number() == 0.0);
    CHECK(r.default_parameters().at(1).at("CAL_ACC0_PRIO").number() == -1.0);
    CHECK(stats.truncated == 0);
    CHECK(stats.unknown_msg_id == 0);
    CHECK(stats.corrupt_regions == 0);
  }
}

// Expected values decoded independently of this reader: a 30-line Python script (struct.unpack on the
// spec's layout) printed the first data message of each topic, at the byte offsets named.
TEST_CASE("ulog reader: data rows decode to the values of an independent decoding" * kNeedsSamples) {
  {
    Reader r(kSamples / "sample.ulg");
    CHECK(r.initial_parameters().at("CAL_MAG0_XOFF").number() == doctest::Approx(0.028247286));
    CHECK(r.initial_parameters().at("CAL_MAG0_XOFF").type == "float");
    CHECK(r.initial_parameters().at("SENS_BOARD_ROT").text() == "0");
    CHECK(r.initial_parameters().at("SENS_BOARD_X_OFF").number() == doctest::Approx(-1.5048006));
    const Collected c = collect(r, "sensor_combined");
    REQUIRE(c.rows.size() == 3);
    const auto& row = c.rows[0];  // the message at byte 36766
    CHECK(row.at("timestamp") == 112614307);
    CHECK(row.at("gyro_rad[0]") == doctest::Approx(-0.001924943644553423).epsilon(1e-7));
    CHECK(row.at("gyro_rad[2]") == doctest::Approx(-0.0032385666854679585).epsilon(1e-7));
    CHECK(row.at("accelerometer_m_s2[2]") == doctest::Approx(-9.63039493560791).epsilon(1e-7));
    CHECK(row.at("magnetometer_timestamp_relative") == -5189);
    CHECK(row.at("magnetometer_ga[1]") == doctest::Approx(0.1450379192829132).epsilon(1e-7));
    CHECK(row.at("baro_timestamp_relative") == 2147483647);  // PX4's "no new baro sample" marker
    CHECK(c.rows[1].at("timestamp") == 112650307);
  }
  {
    Reader r(kSamples / "sample_log_small.ulg");
    CHECK(r.version() == 1);
    CHECK(r.info().at("ver_sw_branch").text() == "v1.11.2_w_rc_sysid");
    CHECK(r.info().at("sys_os_ver_release").number() == 134349055);
    const Collected c = collect(r, "vehicle_gps_position");
    REQUIRE(c.rows.size() >= 2);
    const auto& row = c.rows[0];  // the message at byte 65911
    CHECK(row.at("timestamp") == 20471648);
    CHECK(row.at("time_utc_usec") == 1618986658600345.0);
    CHECK(row.at("lat") == 634170622);
    CHECK(row.at("lon") == 104082151);
    CHECK(row.at("alt") == 66814);
    CHECK(row.at("vel_d_m_s") == doctest::Approx(0.242000013589859).epsilon(1e-7));
    CHECK(row.at("fix_type") == 3);
    CHECK(row.at("satellites_used") == 15);
    CHECK(std::isnan(row.at("heading")));
    CHECK(c.rows[1].at("lat") == 634170612);
    CHECK(c.topics.at("sensor_mag (1, 41)").count > 0);  // multi instances are kept apart
  }
}

TEST_CASE("ulog reader: nested types and padding are flattened as pyulog does" * kNeedsSamples) {
  Reader r(kSamples / "sample.ulg");
  const Subscription* triplet = nullptr;
  std::vector<std::unique_ptr<Subscription>> keep;
  DataHandler h;
  h.on_subscription = [&](const Subscription& s) {
    if (s.name == "position_setpoint_triplet") keep.push_back(std::make_unique<Subscription>(s.name, s.multi_id, s.msg_id, r.formats()));
  };
  r.read_data(h);
  REQUIRE(keep.size() == 1);
  triplet = keep[0].get();
  REQUIRE(triplet->field("current.lat") != nullptr);
  CHECK(triplet->field("next.acceleration_is_force") != nullptr);
  for (const auto& f : triplet->fields()) CHECK(f.name.find("_padding") == std::string::npos);
  CHECK(triplet->size() == 327);  // 327 bytes of fields, then 1 byte of trailing padding
  CHECK(triplet->padded_size() == 328);
  // "timestamp;uint8_t nav_state;uint8_t[7] _padding0;position_setpoint previous;...", and position_setpoint
  // (104 bytes) ends in "uint8_t[1] _padding0": padding inside a nested type moves the offsets after it.
  CHECK(triplet->field("previous.lat")->offset == 8 + 1 + 7 + 8);
  CHECK(triplet->field("current.timestamp")->offset == 16 + 104);
  CHECK(triplet->field("current.lat")->offset == 16 + 104 + 8);
}

TEST_CASE("ulog reader: corrupt and cut files give one line naming the file and the byte, or a counted warning" * kNeedsSamples) {
  const std::string good = file_bytes(kSamples / "sample.ulg");
  const std::string small = file_bytes(kSamples / "sample_log_small.ulg");

  SUBCASE("a flipped byte in the file header") {
    std::string bad = good;
    bad[1] ^= 0x20;
    const fs::path p = scratch_copy("magic.ulg", bad);
    const std::string e = error_reading(p);
    CHECK(e == p.string() + ": byte 0: no ULog magic (\"ULog\" 01 12 35): not a ULog file, or its header is corrupt");
    fs::remove(p);
  }
  SUBCASE("cut in the definitions") {
    const fs::path p = scratch_copy("cut_defs.ulg", good.substr(0, 20000));
    const std::string e = error_reading(p);
    CHECK(e.rfind(p.string() + ": byte ", 0) == 0);
    CHECK(e.find("file cut short in the definitions section") != std::string::npos);
    CHECK(e.find('\n') == std::string::npos);
    fs::remove(p);
  }
  SUBCASE("a format message whose text is corrupt") {
    std::string bad = good;
    const auto at = bad.find("vehicle_attitude:");
    REQUIRE(at != std::string::npos);
    bad[at + 16] = 'X';  // no ':' left in it
    const fs::path p = scratch_copy("format.ulg", bad);
    const std::string e = error_reading(p);
    CHECK(e.find(p.string() + ": byte " + std::to_string(at - 3) + ": format message ('F'): format 'vehicle_attitudeX") == 0);
    fs::remove(p);
  }
  SUBCASE("cut in the middle of the data: a warning, the data before the cut kept") {
    const fs::path p = scratch_copy("cut_data.ulg", good.substr(0, 36766 + 40));  // inside the first sensor_combined message
    Reader r(p);
    const Collected c = collect(r);
    CHECK(c.stats.truncated == 1);
    CHECK(c.stats.first_problem_offset == 36766);
    CHECK(c.topics.count("sensor_combined (0, 72)") == 0);
    CHECK(c.topics.at("vehicle_attitude (0, 36)").count == 1);
    const auto w = c.stats.warnings(p.string());
    REQUIRE(w.size() == 1);
    CHECK(w[0] == p.string() +
                      ": 1 message(s) cut short at the end of the data (a log whose writer stopped): dropped (the first problem in the "
                      "data at byte 36766)");
    fs::remove(p);

    const fs::path half = scratch_copy("half.ulg", good.substr(0, good.size() / 2));
    Reader r2(half);
    const Collected c2 = collect(r2);
    CHECK(c2.stats.truncated == 1);
    CHECK(c2.topics.at("sensor_combined (0, 72)").count > 17070 / 3);
    fs::remove(half);
  }
  SUBCASE("a corrupt message header in the data section: resync at the next sync marker, or the data ends there") {
    std::string bad = good;
    bad[36766 + 2] = 0;  // the first sensor_combined message's type byte; this log has no sync markers
    const fs::path p = scratch_copy("nosync.ulg", bad);
    Reader r0(p);
    const Collected c0 = collect(r0);
    CHECK(c0.stats.unread_from == 36766);
    CHECK(c0.stats.unread_bytes == good.size() - 36766);
    CHECK(c0.topics.count("sensor_combined (0, 72)") == 0);
    CHECK(c0.topics.at("vehicle_attitude (0, 36)").count == 1);  // what came before it kept
    const auto w = c0.stats.warnings(p.string());
    REQUIRE(w.size() == 1);
    CHECK(w[0] == p.string() +
                      ": byte 36766: corrupt message header (type 0x00, size 74), and no sync marker after it to resume from: "
                      "the data ends there (the last " +
                      std::to_string(good.size() - 36766) + " bytes not read)");
    fs::remove(p);

    std::string bad2 = small;
    bad2[62512 + 2] = 0;  // sample_log_small has 12 sync messages (the first at byte 111248)
    const fs::path p2 = scratch_copy("sync.ulg", bad2);
    Reader r(p2);
    const Collected c = collect(r);
    CHECK(c.stats.corrupt_regions == 1);
    CHECK(c.stats.first_problem_offset == 62512);
    CHECK(c.messages == lines_of(kSamples / "sample_log_small_messages.txt"));
    fs::remove(p2);
  }
  SUBCASE("unknown incompatible flag bits: the spec forbids reading the log") {
    std::string bad = small;
    REQUIRE(bad[16 + 2] == 'B');
    bad[16 + 3 + 8 + 1] = 0x04;  // incompat_flags[1]
    const fs::path p = scratch_copy("incompat.ulg", bad);
    CHECK(error_reading(p) ==
          p.string() + ": byte 16: unknown incompatible flag bits set (incompat_flags[1] = 4): the ULog spec forbids parsing this log");
    fs::remove(p);
  }
  SUBCASE("appended data: the data section resumes at the appended offset") {
    // Mark the data after byte 200000 as appended, and cut a message short just before it: the reader
    // must drop the cut message (counted) and go on reading at the offset.
    std::string bad = small;
    const std::uint64_t data_at = 200000;
    std::uint64_t cut_msg = 62512;  // find the message boundary at or before data_at
    for (std::uint64_t pos = 62512; pos < data_at;) {
      cut_msg = pos;
      pos += 3 + static_cast<std::uint8_t>(bad[pos]) + 256u * static_cast<std::uint8_t>(bad[pos + 1]);
      if (pos >= data_at) break;
    }
    const std::string appended = bad.substr(cut_msg);  // the cut message, whole, starts the appended data
    bad = bad.substr(0, cut_msg + 5) + appended;       // 5 bytes of it left in the original section
    const std::uint64_t offset = cut_msg + 5;
    bad[16 + 3 + 8] = 0x01;  // DATA_APPENDED
    std::memcpy(&bad[16 + 3 + 16], &offset, 8);
    const fs::path p = scratch_copy("appended.ulg", bad);
    Reader r(p);
    REQUIRE(r.appended_offsets() == std::vector<std::uint64_t>{offset});
    const Collected c = collect(r);
    Reader original(kSamples / "sample_log_small.ulg");
    const Collected o = collect(original);
    CHECK(c.stats.truncated == 1);
    CHECK(c.stats.first_problem_offset == cut_msg);
    CHECK(c.topics.size() == o.topics.size());
    for (const auto& [k, t] : o.topics) CHECK(c.topics.at(k).count == t.count);
    fs::remove(p);
  }
}

// ---- tern import ulog ----

namespace {

struct Imported {
  tern::core::ImportReport report;
  fs::path dir;
  std::vector<std::string> lines(const std::string& topic) const { return lines_of(dir / "topics" / (topic + ".csv")); }
};

Imported import_sample(const std::string& name, const fs::path& dir = kSamples, const tern::core::CommandMapping& commands = {}) {
  Imported i;
  i.dir = fs::temp_directory_path() / ("tern_test_ulog_import_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(i.dir);
  tern::core::SensorLogWriter out(i.dir);
  i.report = tern::core::import_ulog(dir / (name + ".ulg"), out, commands);
  return i;
}

bool has_line(const std::vector<std::string>& lines, const std::string& part) {
  return std::count_if(lines.begin(), lines.end(), [&](const std::string& l) { return l.find(part) != std::string::npos; }) == 1;
}

}  // namespace

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string c; std::getline(ss, c, ',');) out.push_back(c);
  return out;
}

TEST_CASE("tern import ulog: sample.ulg (a 2017 quadrotor on the ground: sensor_combined with mag, no GPS)" * kNeedsSamples) {
  const Imported i = import_sample("sample");
  CHECK(i.report.rows.at("imu") == 17070);       // every sensor_combined message (sample_info.txt's count)
  CHECK(i.report.rows.at("mag") == 6759);        // sensor_combined repeats each mag sample until the next: distinct samples
  CHECK(i.report.rows.at("reference") == 6461);  // vehicle_attitude; vehicle_local_position never valid (no GPS)
  CHECK(i.report.rows.count("gnss") == 0);
  CHECK(i.report.rows.count("baro") == 0);       // baro_timestamp_relative is always PX4's "invalid" (the log: no barometer found)
  CHECK(i.report.rows.count("actuators") == 0);  // the full deflections not stated: not written
  CHECK(!fs::exists(i.dir / "topics" / "actuators.csv"));
  const std::string f = (kSamples / "sample.ulg").string();
  CHECK(i.report.warnings ==
        std::vector<std::string>{
            f + ": no baro: vehicle_air_data, sensor_combined.baro_alt_meter or sensor_baro with data",
            f + ": no diff_pressure: differential_pressure or airspeed with data",
            f + ": no gnss: vehicle_gps_position or sensor_gps with data (without GNSS the estimator never initialises)",
            f + ": no reference wind: wind or wind_estimate with data",
            f + ": actuator_controls_0 holds the surfaces' commands, normalised: no actuators.csv written without --max-deflection A E R "
                "(rad: the full aileron, elevator and rudder deflections, the aircraft file's servos.max_delta_a/e/r; a ULog does not "
                "hold them)",
            f + ": 4 logging dropout(s), 119 ms in all: data lost by PX4's logger",
            f + ": no GNSS fix with a UTC time: the flight's date is unknown (the magnetic model's date is not set)",
        });
  // The header's start timestamp is 112500176 us; the first sensor_combined message (byte 36766,
  // decoded independently above) is at 112614307 us with its magnetometer sample 5189 us earlier.
  const auto imu = cells(i.lines("imu").at(1));
  CHECK(i.lines("imu").at(0) ==
        "t [s],stamp [ns],accel_x [m/s^2],accel_y [m/s^2],accel_z [m/s^2],gyro_x [rad/s],gyro_y [rad/s],gyro_z [rad/s],temperature [K]");
  CHECK(imu.at(1) == "114131000");
  CHECK(std::stod(imu.at(4)) == doctest::Approx(-9.63039493560791));
  CHECK(std::stod(imu.at(5)) == doctest::Approx(-0.001924943644553423));
  const auto mag = cells(i.lines("mag").at(1));
  CHECK(mag.at(1) == std::to_string((112614307 - 5189 - 112500176) * 1000));
  CHECK(std::stod(mag.at(2)) == doctest::Approx(0.1216617226600647e-4));  // gauss -> T
  CHECK(std::stod(mag.at(4)) == doctest::Approx(0.44688117504119873e-4));
  // vehicle_attitude at 112574307 us, q = (0.95459, 0.04148, 0.04817, -0.29106): Euler angles from the
  // rotation matrix by a separate Python computation (atan2(R32, R33), -asin(R31), atan2(R21, R11)).
  const auto ref = cells(i.lines("reference").at(1));
  CHECK(ref.at(1) == "74131000");
  CHECK(std::stod(ref.at(2)) == doctest::Approx(0.05151783376879919));
  CHECK(std::stod(ref.at(3)) == doctest::Approx(0.11638264820844389));
  CHECK(std::stod(ref.at(4)) == doctest::Approx(-0.5888995902920631));
  CHECK(ref.at(5) == "nan");
  const YAML::Node meta = YAML::LoadFile((i.dir / "sensor_log.yaml").string());
  CHECK(!meta["date"]);
  CHECK(meta["estimator"]["imu_mount"].as<std::vector<double>>() == std::vector<double>{0, 0, 0});
  fs::remove_all(i.dir);
}

TEST_CASE("tern import ulog: pyulog's appended-data sample (2017, a quadrotor's ground log with data appended after it ended)") {
  const Imported i = import_sample("sample_appended_multiple", fs::path(TERN_SOURCE_DIR) / "tests" / "real_data" / "ulog");
  CHECK(i.report.rows.at("imu") == 2373);  // every sensor_combined message, the appended ones included (pyulog's count)
  // vehicle_attitude's 306 rows (attitude) and vehicle_local_position's 95 (position, velocity), each
  // message its own row at its own stamp (pyulog's counts)
  CHECK(i.report.rows.at("reference") == 306 + 95);
  CHECK(i.report.rows.count("gnss") == 0);
  const auto imu = cells(i.lines("imu").back());
  CHECK(std::stoll(imu.at(1)) <= 9'780'000'000);  // the last row within the log's 9.78 s
  fs::remove_all(i.dir);
}

TEST_CASE("tern import ulog: sample_log_small.ulg (a 2021 VTOL armed on the ground: GPS, air data, airspeed)" * kNeedsSamples) {
  const Imported i = import_sample("sample_log_small");
  Reader r(kSamples / "sample_log_small.ulg");
  for (const char* t : {"imu", "mag", "baro", "diff_pressure", "gnss", "reference"}) CHECK(i.report.rows.count(t) == 1);
  CHECK(i.report.rows.at("gnss") == 32);
  CHECK(i.report.rows.at("diff_pressure") == 6);
  // vehicle_gps_position at byte 65911 (decoded independently above): timestamp 20471648 us, lat 634170622,
  // lon 104082151 (1e-7 deg), alt 66814 mm, vel_d 0.242 m/s, eph 3.26, epv 6.984, s_variance_m_s 0.651,
  // fix_type 3, 15 satellites; the header's start timestamp is 20309082 us.
  const auto g = cells(i.lines("gnss").at(1));
  CHECK(g.at(1) == std::to_string((20471648 - 20309082) * 1000));
  CHECK(g.at(2) == "0");  // this PX4 version's vehicle_gps_position has no timestamp_sample
  CHECK(g.at(3) == "3");
  CHECK(g.at(4) == "15");
  CHECK(std::stod(g.at(5)) == doctest::Approx(63.4170622).epsilon(1e-12));
  CHECK(std::stod(g.at(6)) == doctest::Approx(10.4082151).epsilon(1e-12));
  CHECK(std::stod(g.at(7)) == doctest::Approx(66.814));
  CHECK(std::stod(g.at(10)) == doctest::Approx(0.242000013589859));
  CHECK(std::stod(g.at(11)) == doctest::Approx(3.26));
  CHECK(std::stod(g.at(12)) == doctest::Approx(6.984));
  CHECK(std::stod(g.at(13)) == doctest::Approx(0.651));
  const auto b = cells(i.lines("baro").at(1));
  CHECK(std::stod(b.at(2)) > 95000.0);  // Pa (vehicle_air_data.baro_pressure_pa), near sea level in Trondheim
  CHECK(std::stod(b.at(2)) < 105000.0);
  const YAML::Node meta = YAML::LoadFile((i.dir / "sensor_log.yaml").string());
  CHECK(meta["date"].as<std::string>() == "2021-04-21");  // time_utc_usec 1618986658600345
  CHECK(meta["estimator"]["gnss_delay"].as<double>() == doctest::Approx(r.initial_parameters().at("EKF2_GPS_DELAY").number() * 1e-3));
  CHECK(meta["estimator"]["diff_pressure_delay"].as<double>() ==
        doctest::Approx(r.initial_parameters().at("EKF2_ASP_DELAY").number() * 1e-3));
  CHECK(meta["estimator"]["gnss_antenna_position"].as<std::vector<double>>().size() == 3);
  fs::remove_all(i.dir);
}

/// `bytes` with `from` replaced by the same-length `to` at every place `where` accepts (its offset).
std::string patched(std::string bytes, const std::string& from, const std::string& to, const std::function<bool(std::size_t)>& where) {
  REQUIRE(from.size() == to.size());
  int n = 0;
  for (std::size_t at = bytes.find(from); at != std::string::npos; at = bytes.find(from, at + 1))
    if (where(at)) bytes.replace(at, from.size(), to), ++n;
  REQUIRE(n > 0);
  return bytes;
}

TEST_CASE("tern import ulog: actuator_controls_0 -> actuators, the uavbook's signs, stamps at publication (sample.ulg)" * kNeedsSamples) {
  tern::core::CommandMapping m;
  m.max_deflection = std::array<double, 3>{0.35, 0.30, 0.40};
  m.command_delay = 0.02;
  const Imported i = import_sample("sample", kSamples, m);
  CHECK(i.report.rows.at("actuators") == 3269);  // every actuator_controls_0 message (sample_info.txt's count)
  CHECK(i.report.rows.at("imu") == 17070);       // the sensors as without the option
  const std::string f = (kSamples / "sample.ulg").string();
  CHECK(has_line(i.report.warnings, f + ": MAV_TYPE 2 is no fixed wing: actuator_controls_0's roll, pitch and yaw are the rotors' torque"));
  CHECK(has_line(
      i.report.warnings,
      f + ": the surfaces' commands are logged at 47.4 Hz, below the 50 Hz sysid needs (a held command lags half a sample, 11 ms: 15 "
          "deg of phase at 3.95 Hz)"));
  CHECK(i.lines("actuators").at(0) == "t [s],stamp [ns],delta_a [rad],delta_e [rad],delta_r [rad],delta_t [],brake []");
  // The first actuator_controls_0 message, decoded independently (Python struct on the file): timestamp
  // 112574774 us (timestamp_sample 112574307), control = (-0.04677823930978775, -0.09784627705812454,
  // -0.04372883960604668, 0): PX4's roll left, nose down, yaw left. The header's start is 112500176 us.
  const auto a = cells(i.lines("actuators").at(1));
  CHECK(a.at(1) == std::to_string((112574774 - 112500176) * 1000 + 20'000'000));             // + --command-delay 0.02 s
  CHECK(std::stod(a.at(2)) == doctest::Approx(-0.04677823930978775 * 0.35).epsilon(1e-12));  // roll left: delta_a < 0
  CHECK(std::stod(a.at(3)) == doctest::Approx(0.09784627705812454 * 0.30).epsilon(1e-12));   // nose down: delta_e > 0
  CHECK(std::stod(a.at(4)) == doctest::Approx(0.04372883960604668 * 0.40).epsilon(1e-12));   // yaw left: delta_r > 0
  CHECK(a.at(5) == "0");
  CHECK(a.at(6) == "0");
  const YAML::Node meta = YAML::LoadFile((i.dir / "sensor_log.yaml").string());
  std::vector<std::string> notes;
  for (const auto& n : meta["notes"]) notes.push_back(n.as<std::string>());
  CHECK(has_line(notes,
                 "actuators: full deflections (--max-deflection) aileron 0.35 rad (20.1 deg), elevator 0.3 rad (17.2 deg), rudder "
                 "0.4 rad (22.9 deg), stated at import, not in the log"));
  CHECK(has_line(notes, "+ 0.02 s (--command-delay); the latency from there to the surface is not in the log"));
  CHECK(has_line(notes, "actuators: actuator_controls_0 published 0.6 ms (mean; at most 2.1 ms) after the gyro sample"));
  fs::remove_all(i.dir);
}

TEST_CASE("tern import ulog: a VTOL's surfaces from its fixed-wing group actuator_controls_1 (sample_log_small.ulg)" * kNeedsSamples) {
  tern::core::CommandMapping m;
  m.max_deflection = std::array<double, 3>{0.5, 0.4, 0.3};
  const Imported i = import_sample("sample_log_small", kSamples, m);
  CHECK(i.report.rows.at("actuators") == 1812);  // actuator_controls_1's messages (MAV_TYPE 22: a VTOL)
  for (const auto& w : i.report.warnings) CHECK(w.find("actuator") == std::string::npos);  // 279 Hz, a fixed wing's group
  // actuator_controls_1's first message: timestamp 20327133 us, control = (-0.19372718036174774,
  // -0.021825987845659256, 0, 0); the header's start is 20309082 us
  const auto a = cells(i.lines("actuators").at(1));
  CHECK(a.at(1) == std::to_string((20327133 - 20309082) * 1000));
  CHECK(std::stod(a.at(2)) == doctest::Approx(-0.19372718036174774 * 0.5).epsilon(1e-12));
  CHECK(std::stod(a.at(3)) == doctest::Approx(0.021825987845659256 * 0.4).epsilon(1e-12));
  CHECK(a.at(4) == "0");
  fs::remove_all(i.dir);
}

TEST_CASE("tern import ulog: an actuator topic malformed or empty: one line naming it, the sensors imported" * kNeedsSamples) {
  tern::core::CommandMapping m;
  m.max_deflection = std::array<double, 3>{0.35, 0.30, 0.40};
  const std::string good = file_bytes(kSamples / "sample.ulg");
  const std::string format = "actuator_controls_0:uint64_t timestamp;uint64_t timestamp_sample;float[8] control";
  SUBCASE("actuator_controls_0's format without control[]") {
    const fs::path p = scratch_copy(
        "act_malformed.ulg", patched(good, format, format.substr(0, format.size() - 7) + "kontrol", [](std::size_t) { return true; }));
    const Imported i = import_sample(p.stem().string(), p.parent_path(), m);
    CHECK(i.report.rows.at("imu") == 17070);
    CHECK(i.report.rows.count("actuators") == 0);
    CHECK(has_line(i.report.warnings, p.string() + ": topic actuator_controls_0 has no fields control[0..3] (roll, pitch, yaw, throttle): "
                                                   "no actuators.csv written; the sensors are imported"));
    fs::remove_all(i.dir);
    fs::remove(p);
  }
  SUBCASE("actuator_controls_0 subscribed as actuator_controls_2: no actuator_controls_0 data") {
    // the add-logged message names the topic without the format's ':'; actuator_controls_2 has the same format
    const fs::path p = scratch_copy("act_empty.ulg", patched(good, "actuator_controls_0", "actuator_controls_2", [&good](std::size_t at) {
                                      return good[at + std::strlen("actuator_controls_0")] != ':';
                                    }));
    const Imported i = import_sample(p.stem().string(), p.parent_path(), m);
    CHECK(i.report.rows.at("imu") == 17070);
    CHECK(i.report.rows.count("actuators") == 0);
    CHECK(has_line(i.report.warnings, p.string() + ": no surface commands in this log (neither actuator_controls_0 nor actuator_servos "
                                                   "holds data): no actuators.csv written (tern sysid needs one)"));
    fs::remove_all(i.dir);
    fs::remove(p);
  }
}

/// A ULog file written byte by byte (the spec's header, then 'F', 'P', 'A' and 'D' messages; no flag
/// bits message, which the spec makes optional).
class UlogBytes {
 public:
  explicit UlogBytes(std::uint64_t start_us) {
    bytes_ = std::string("ULog\x01\x12\x35", 7) + std::string(1, '\x01');
    put(start_us);
  }
  void format(const std::string& text) { message('F', text); }
  template <class T>
  void param(const std::string& type, const std::string& name, T value) {
    const std::string key = type + " " + name;
    message('P', std::string(1, static_cast<char>(key.size())) + key + raw(value));
  }
  void subscribe(std::uint16_t id, const std::string& topic) { message('A', std::string(1, '\0') + raw(id) + topic); }
  /// A data message of subscription `id`: the timestamp, then floats.
  void data(std::uint16_t id, std::uint64_t t_us, const std::vector<float>& values) {
    std::string p = raw(id) + raw(t_us);
    for (float v : values) p += raw(v);
    message('D', p);
  }
  const std::string& bytes() const { return bytes_; }

 private:
  template <class T>
  static std::string raw(T v) {
    std::string s(sizeof v, '\0');
    std::memcpy(s.data(), &v, sizeof v);
    return s;
  }
  template <class T>
  void put(T v) {
    bytes_ += raw(v);
  }
  void message(char type, const std::string& payload) {
    put(static_cast<std::uint16_t>(payload.size()));
    bytes_ += type;
    bytes_ += payload;
  }
  std::string bytes_;
};

TEST_CASE("tern import ulog: PX4 v1.13+'s actuator_servos through the surfaces' torque effectiveness, throttle from actuator_motors") {
  // a conventional fixed wing as PX4's control allocation describes it: left and right aileron (roll
  // -0.5, +0.5), elevator (pitch 1), rudder (yaw 1), one pusher motor
  UlogBytes u(1'000'000);
  u.format("sensor_combined:uint64_t timestamp;float[3] gyro_rad;float[3] accelerometer_m_s2");
  u.format("actuator_servos:uint64_t timestamp;float[8] control");
  u.format("actuator_motors:uint64_t timestamp;float[4] control");
  u.param<std::int32_t>("int32_t", "MAV_TYPE", 1);
  u.param<std::int32_t>("int32_t", "CA_AIRFRAME", 1);
  u.param<std::int32_t>("int32_t", "CA_ROTOR_COUNT", 1);
  u.param<std::int32_t>("int32_t", "CA_SV_CS_COUNT", 4);
  const std::vector<std::array<float, 3>> trq = {{-0.5f, 0, 0}, {0.5f, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int i = 0; i < 4; ++i) {
    u.param<std::int32_t>("int32_t", "CA_SV_CS" + std::to_string(i) + "_TYPE", i + 1);  // 1-4: left, right aileron, elevator, rudder
    for (int a = 0; a < 3; ++a) u.param<float>("float", "CA_SV_CS" + std::to_string(i) + "_TRQ_" + "RPY"[a], trq[i][a]);
  }
  u.subscribe(0, "sensor_combined");
  u.subscribe(1, "actuator_servos");
  u.subscribe(2, "actuator_motors");
  for (int k = 0; k < 20; ++k) u.data(0, 1'000'000 + 4000 * k, {0, 0, 0, 0, 0, static_cast<float>(-tern::kStandardGravity)});
  u.data(2, 1'010'000, {0.6f, 0, 0, 0});
  // left aileron -0.2 and right +0.2 (roll right), elevator +0.3 (PX4: nose up), rudder -0.1 (yaw left)
  u.data(1, 1'012'000, {-0.2f, 0.2f, 0.3f, -0.1f, 0, 0, 0, 0});
  u.data(1, 1'032'000, {0.1f, 0.3f, 0, 0, 0, 0, 0, 0});  // ailerons 0.1 and 0.3: roll 0.1, half their difference
  const fs::path p = scratch_copy("servos.ulg", u.bytes());
  tern::core::CommandMapping m;
  m.max_deflection = std::array<double, 3>{0.35, 0.30, 0.40};
  const Imported i = import_sample(p.stem().string(), p.parent_path(), m);
  CHECK(i.report.rows.at("imu") == 20);
  REQUIRE(i.report.rows.at("actuators") == 2);
  const auto a = cells(i.lines("actuators").at(1));
  CHECK(a.at(1) == "12000000");                                             // 1012000 us - the start 1000000 us
  CHECK(std::stod(a.at(2)) == doctest::Approx(0.2 * 0.35).epsilon(1e-6));   // roll right: delta_a > 0
  CHECK(std::stod(a.at(3)) == doctest::Approx(-0.3 * 0.30).epsilon(1e-6));  // nose up: delta_e < 0
  CHECK(std::stod(a.at(4)) == doctest::Approx(0.1 * 0.40).epsilon(1e-6));   // yaw left: delta_r > 0
  CHECK(std::stod(a.at(5)) == doctest::Approx(0.6).epsilon(1e-6));          // the motor in force
  const auto b = cells(i.lines("actuators").at(2));
  CHECK(std::stod(b.at(2)) == doctest::Approx(0.1 * 0.35).epsilon(1e-6));
  CHECK(b.at(3) == "0");
  fs::remove_all(i.dir);
  fs::remove(p);
}

TEST_CASE("tern import ulog: a parameter not a number, a time beyond any clock, a format holding a newline: one ImportError line") {
  // fuzz_ulog_conversion's findings: std::invalid_argument and std::runtime_error escaped import_ulog
  // (tern import then named no file and left its sensor log behind), and an error quoted the file raw
  const auto import_error = [](const std::string& name, const UlogBytes& u) {
    const fs::path p = scratch_copy(name + ".ulg", u.bytes());
    std::string e;
    try {
      (void)import_sample(p.stem().string(), p.parent_path());
    } catch (const tern::core::ImportError& x) {
      e = x.what();
    }
    fs::remove_all(fs::temp_directory_path() / ("tern_test_ulog_import_" + std::to_string(::getpid()) + "_" + p.stem().string()));
    fs::remove(p);
    CHECK(e.rfind(p.string() + ": ", 0) == 0);
    CHECK(e.find('\n') == std::string::npos);
    return e.substr(std::min(e.size(), p.string().size() + 2));
  };
  const auto imu = [](UlogBytes& u) {
    u.format("sensor_combined:uint64_t timestamp;float[3] gyro_rad;float[3] accelerometer_m_s2");
    u.subscribe(0, "sensor_combined");
  };
  {
    UlogBytes u(1'000'000);
    u.param<std::uint32_t>("char[4]", "EKF2_GPS_DELAY", 0x41414141);  // in the definitions: before the subscriptions
    imu(u);
    u.data(0, 1'004'000, {0, 0, 0, 0, 0, -9.8f});
    CHECK(import_error("param_text", u) == "parameter 'EKF2_GPS_DELAY': ulog value of type 'char[4]' is not a number");
  }
  {
    UlogBytes u(1'000'000);
    imu(u);
    u.data(0, std::uint64_t{1} << 62, {0, 0, 0, 0, 0, -9.8f});
    CHECK(import_error("far_future", u) ==
          "timestamp 4611686018427387904 us: beyond any clock's range after the log's start (1000000 us): a corrupt file?");
  }
  {
    UlogBytes u(1'000'000);
    u.param<float>("float", "MAV_TYPE", 1e20f);  // converting it to int was undefined behaviour
    imu(u);
    u.data(0, 1'004'000, {0, 0, 0, 0, 0, -9.8f});
    CHECK(import_error("mav_type_float", u) == "parameter 'MAV_TYPE': 1e+20 is not an integer");
  }
  {
    UlogBytes u(1'000'000);
    u.format("sensor\ncombined");
    CHECK(import_error("newline_format", u) == "byte 16: format message ('F'): format 'sensor\\ncombined' has no 'name:'");
  }
}

TEST_CASE("tern import ulog: CA_ROTOR_COUNT 2^31 - 1 looks at actuator_motors' own controls only (it looped for minutes)") {
  UlogBytes u(1'000'000);
  u.format("sensor_combined:uint64_t timestamp;float[3] gyro_rad;float[3] accelerometer_m_s2");
  u.format("actuator_servos:uint64_t timestamp;float[8] control");
  u.format("actuator_motors:uint64_t timestamp;float[4] control");
  u.param<std::int32_t>("int32_t", "CA_AIRFRAME", 1);
  u.param<std::int32_t>("int32_t", "CA_ROTOR_COUNT", 2147483647);
  u.param<std::int32_t>("int32_t", "CA_SV_CS_COUNT", 1);
  u.param<float>("float", "CA_SV_CS0_TRQ_R", 1.0f);
  u.subscribe(0, "sensor_combined");
  u.subscribe(1, "actuator_servos");
  u.subscribe(2, "actuator_motors");
  u.data(0, 1'004'000, {0, 0, 0, 0, 0, static_cast<float>(-tern::kStandardGravity)});
  u.data(2, 1'005'000, {0.2f, 0.4f, 0, 0});
  u.data(1, 1'006'000, {0.5f, 0, 0, 0, 0, 0, 0, 0});
  const fs::path p = scratch_copy("rotors.ulg", u.bytes());
  tern::core::CommandMapping m;
  m.max_deflection = std::array<double, 3>{0.35, 0.30, 0.40};
  const Imported i = import_sample(p.stem().string(), p.parent_path(), m);
  REQUIRE(i.report.rows.at("actuators") == 1);
  CHECK(std::stod(cells(i.lines("actuators").at(1)).at(5)) == doctest::Approx(0.15).epsilon(1e-6));  // the mean of the 4 motors
  fs::remove_all(i.dir);
  fs::remove(p);
}

TEST_CASE("tern import ulog --max-deflection: actuators.csv written; a deflection not in rad: one error line" * kNeedsSamples) {
  const fs::path tmp = fs::temp_directory_path() / ("tern_test_ulog_act_cli_" + std::to_string(::getpid()));
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  const std::string ulg = (kSamples / "sample_log_small.ulg").string();
  REQUIRE(run_tern({"import", "ulog", ulg, (tmp / "log").string(), "--max-deflection", "0.35", "0.3", "0.4"}, tmp / "import.txt") == 0);
  const auto printed = lines_of(tmp / "import.txt");
  CHECK(std::count_if(printed.begin(), printed.end(), [](const std::string& l) {
          return l.find("actuators") != std::string::npos && l.find(" 1812 rows") != std::string::npos;
        }) == 1);
  CHECK(run_tern({"import", "ulog", ulg, (tmp / "log2").string(), "--max-deflection", "35", "0.3", "0.4"}, tmp / "bad.txt") == 1);
  CHECK(lines_of(tmp / "bad.txt") ==
        std::vector<std::string>{"tern: error: import: --max-deflection 35: each full deflection is in rad, above 0 and below pi/2"});
  CHECK(!fs::exists(tmp / "log2"));
  fs::remove_all(tmp);
}

TEST_CASE("tern import ulog: the conversions, on hand-checked values") {
  using namespace tern::core::ulog_import;
  using tern::msg::FixType;
  CHECK(px4_fix_type(0) == FixType::none);
  CHECK(px4_fix_type(1) == FixType::none);
  CHECK(px4_fix_type(2) == FixType::fix_2d);
  CHECK(px4_fix_type(6) == FixType::fix_3d);
  CHECK(px4_fix_type(8) == FixType::dead_reckoning);
  const double h = std::sqrt(0.5);
  const Euler yaw = euler_from_px4_quaternion(h, 0, 0, h);  // 90 deg about down: nose east
  CHECK(yaw.psi == doctest::Approx(M_PI / 2));
  CHECK(yaw.phi == doctest::Approx(0.0));
  const Euler roll =
      euler_from_px4_quaternion(2 * std::cos(M_PI / 12), 2 * std::sin(M_PI / 12), 0, 0);  // 30 deg right wing down, unnormalised
  CHECK(roll.phi == doctest::Approx(M_PI / 6));
  CHECK(roll.theta == doctest::Approx(0.0));
  const LatLon north = px4_reproject(0.0, 0.0, 1000.0, 0.0);  // 1 km along a meridian of the 6371 km sphere
  CHECK(north.lat == doctest::Approx(1000.0 / 6371000.0 * 180.0 / M_PI).epsilon(1e-12));
  CHECK(north.lon == doctest::Approx(0.0));
  const LatLon east = px4_reproject(60.0, 10.0, 0.0, 1000.0);  // at 60 deg N a degree of longitude is half as long
  CHECK(east.lon - 10.0 == doctest::Approx(2 * 1000.0 / 6371000.0 * 180.0 / M_PI).epsilon(1e-6));
  CHECK(east.lat == doctest::Approx(60.0).epsilon(1e-6));
  CHECK(iso_date_from_utc_usec(1618986658600345ull) == "2021-04-21");
  CHECK(iso_date_from_utc_usec(8'385'000'000'000'000'000ull) == "");  // year 267695 (fuzz_ulog_conversion): no date

  std::vector<tern::Nanos> out;
  ReorderWindow<tern::msg::Mag> w(100, [&](const tern::msg::Mag& m) { out.push_back(m.stamp); });
  for (tern::Nanos t : {10, 30, 20, 150, 140, 400, 100, 500}) {  // 100 arrives after 400 released everything up to 300
    tern::msg::Mag m;
    m.stamp = t;
    w.push(m);
  }
  w.flush();
  CHECK(out == std::vector<tern::Nanos>{10, 20, 30, 140, 150, 400, 500});
  CHECK(w.dropped() == 1);
}

TEST_CASE("tern import ulog FILE DIR, then tern replay DIR: every imported sensor row reaches the estimator" * kNeedsSamples) {
  const fs::path tmp = fs::temp_directory_path() / ("tern_test_ulog_cli_" + std::to_string(::getpid()));
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  const fs::path log = tmp / "log";
  REQUIRE(run_tern({"import", "ulog", (kSamples / "sample_log_small.ulg").string(), log.string()}, tmp / "import.txt") == 0);
  const auto printed = lines_of(tmp / "import.txt");
  CHECK(std::count_if(printed.begin(), printed.end(), [](const std::string& l) {
          return l.find("gnss") != std::string::npos && l.find(" 32 rows") != std::string::npos;
        }) == 1);
  REQUIRE(fs::exists(log / "topics" / "imu.csv"));
  REQUIRE(fs::exists(log / "sensor_log.yaml"));

  REQUIRE(run_tern({"replay", log.string(), "--log-dir", (tmp / "runs").string(), "-q"}, tmp / "replay.txt") == 0);
  std::vector<fs::path> runs;
  for (const auto& e : fs::directory_iterator(tmp / "runs")) runs.push_back(e.path());
  REQUIRE(runs.size() == 1);
  std::ifstream in(runs[0] / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  const auto& ekf = summary.at("instances").at("ekf");
  CHECK(ekf.at("gnss_received").get<double>() == 32);
  CHECK(ekf.at("mag_received").get<double>() == 319);
  CHECK(ekf.at("baro_received").get<double>() == 119);
  CHECK(ekf.at("diff_pressure_received").get<double>() == 6);
  CHECK(ekf.at("imu_received").get<double>() >= 1297);  // the last IMU row may end the replay
  CHECK(ekf.at("gnss_invalid").get<double>() == 0);
  CHECK(ekf.at("mag_invalid").get<double>() == 0);
  fs::remove_all(tmp);
}

TEST_CASE("tern import ulog on a file cut in its definitions: one error line, exit 1, no output left" * kNeedsSamples) {
  const fs::path tmp = fs::temp_directory_path() / ("tern_test_ulog_cut_" + std::to_string(::getpid()));
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  const fs::path cut = scratch_copy("cli_cut.ulg", file_bytes(kSamples / "sample.ulg").substr(0, 20000));
  CHECK(run_tern({"import", "ulog", cut.string(), (tmp / "log").string()}, tmp / "out.txt") == 1);
  CHECK(lines_of(tmp / "out.txt") ==
        std::vector<std::string>{
            "tern: error: import: " + cut.string() +
            ": byte 19811: file cut short in the definitions section (189 bytes left for a message header and payload)"});
  CHECK(!fs::exists(tmp / "log"));
  fs::remove(cut);
  fs::remove_all(tmp);
}
