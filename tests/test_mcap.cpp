// The MCAP flight log alone (mcap/mcap_*.hpp, FlightLog with log.format both), no flight: a
// written file read back record by record, the same captures giving the same bytes whatever the
// flushes, `tern export csv`'s tables equal to the CSV log's byte for byte (NaN, infinities,
// -0, integer extremes, bools included), the open chunk on disk after a flush, and recovery of a
// file cut at many offsets: every message of the chunks before the cut, in order, nothing else.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include "ros/cdr_columns.hpp"
#include "record/flight_log.hpp"
#include "export/mcap_csv_export.hpp"
#include "mcap/mcap_reader.hpp"
#include "mcap/mcap_recover.hpp"
#include "ros/ros_channels.hpp"
#include "tern/msg/all.hpp"
#include "test_util.hpp"

using namespace tern;
using namespace tern::core;

namespace {

struct Logged {
  std::string topic;
  std::uint64_t log_time;
  std::string data;
  bool operator==(const Logged&) const = default;
};

/// Every message of an MCAP file in file order, and the attachments' names.
std::vector<Logged> messages_of(const fs::path& file, std::vector<std::string>* attachments = nullptr, std::string* stopped = nullptr) {
  McapReader in(file);
  std::map<std::uint16_t, std::string> topics;
  std::vector<Logged> out;
  McapRecord r;
  std::string buffer;
  auto add = [&](const McapMessage& m) { out.push_back({topics.at(m.channel), m.log_time, std::string(m.data)}); };
  while (in.next(r)) {
    if (r.op == mcap::Op::channel) {
      const McapChannel c = in.channel(r);
      topics[c.id] = c.topic;
    } else if (r.op == mcap::Op::chunk) {
      in.chunk_messages(r, buffer, add);
    } else if (r.op == mcap::Op::attachment && attachments != nullptr) {
      attachments->push_back(in.attachment(r).name);
    }
  }
  if (stopped != nullptr) *stopped = in.truncated();
  return out;
}

msg::Imu imu_at(int k) {
  msg::Imu m;
  m.stamp = Nanos{k} * 2'500'000;
  m.accel = Eigen::Vector3d(0.1 * k, -9.80665 + 1e-17 * k, k % 7 == 0 ? -0.0 : 1.0 / (k + 3));
  m.gyro = Eigen::Vector3d(k % 11 == 0 ? std::nan("") : 1e-300 * k, k % 13 == 0 ? -std::numeric_limits<double>::infinity() : 0.5,
                           3.0e8 / (k + 1));
  m.temperature = 288.15 + 0.001 * k;
  return m;
}

msg::Gnss gnss_at(int k) {
  msg::Gnss g;
  g.stamp = Nanos{k} * 100'000'000;
  g.fix_type = static_cast<msg::FixType>(k % 4);
  g.num_sats = static_cast<std::uint8_t>(255 - k % 256);
  g.lat = 47.397742 + 1e-9 * k;
  g.lon = -122.0 - 1e-9 * k;
  return g;
}

/// A log of `n` IMU messages (400 Hz) and a GNSS fix every 40th, flushed every `flush_every`
/// captures (0: never before close); returns its run directory.
fs::path write_log(const std::string& name, const FlightLog::Format& format, int n, int flush_every) {
  const fs::path dir = test_dir() / name;
  FlightLog log(dir, {}, format);
  log.write_file("config.yaml", "name: mcap\nseed: 1\n");
  log.param(0, "ekf.gain", "2.5", "config");
  const auto imu = log.add_topic("imu", reflect::layout<msg::Imu>(), sizeof(msg::Imu), msg::Imu::type_name);
  const auto gnss = log.add_topic("gnss", reflect::layout<msg::Gnss>(), sizeof(msg::Gnss), msg::Gnss::type_name);
  for (int k = 0; k < n; ++k) {
    const msg::Imu m = imu_at(k);
    log.capture(imu, m.stamp, &m);
    if (k % 40 == 0) {
      const msg::Gnss g = gnss_at(k / 40);
      log.capture(gnss, m.stamp, &g);
    }
    if (flush_every > 0 && k % flush_every == flush_every - 1) log.flush();
  }
  log.write_file("summary.json", "{\"ok\": true}\n");
  log.close();
  CHECK(log.error() == "");
  return dir;
}

FlightLog::Format both(std::size_t chunk_bytes = 64 * 1024) { return {true, true, chunk_bytes}; }

}  // namespace

TEST_CASE("mcap: a flight log's file reads back: channels, messages in capture order, attachments, summary and footer") {
  const fs::path dir = write_log("mcap_read", both(), 4000, 0);
  std::vector<std::string> attachments;
  std::string stopped = "?";
  const auto msgs = messages_of(dir / "flight.mcap", &attachments, &stopped);
  CHECK(stopped == "");
  REQUIRE(msgs.size() == 4000 + 100);
  CHECK(msgs[0].topic == "/imu");
  CHECK(msgs[1].topic == "/gnss");
  CHECK(msgs[2].topic == "/imu");
  CHECK(msgs[2].log_time == 2'500'000);
  std::string cdr;
  const msg::Imu m = imu_at(1);
  encode_cdr(reflect::layout<msg::Imu>(), reinterpret_cast<const char*>(&m), cdr);
  CHECK(msgs[2].data == cdr);
  CHECK(attachments == std::vector<std::string>{"config.yaml", "params.csv", "summary.json"});
  const std::string bytes = read_file(dir / "flight.mcap");
  REQUIRE(bytes.size() > 8 + 9 + 20);
  CHECK(bytes.substr(bytes.size() - 8) == std::string(mcap::kMagic, 8));
  std::uint64_t summary_start;  // the footer: summary_start, summary_offset_start, crc
  std::memcpy(&summary_start, bytes.data() + bytes.size() - 8 - 20, 8);
  REQUIRE(summary_start < bytes.size());
  CHECK(static_cast<mcap::Op>(bytes[summary_start]) == mcap::Op::schema);
  CHECK(tern_schema_text(reflect::layout<msg::Gnss>()).find("uint8 fix_type  # enum\nuint8 num_sats\nfloat64 lat  # deg\n") !=
        std::string::npos);
}

TEST_CASE("mcap: the same captures give the same bytes, however often the log is flushed") {
  const fs::path a = write_log("mcap_same_a", both(), 3000, 0);
  const fs::path b = write_log("mcap_same_b", both(), 3000, 7);
  const fs::path c = write_log("mcap_same_c", both(), 3000, 333);
  const std::string fa = read_file(a / "flight.mcap");
  CHECK(fa.size() > 1000);
  CHECK(fa == read_file(b / "flight.mcap"));
  CHECK(fa == read_file(c / "flight.mcap"));
}

TEST_CASE("mcap: tern export csv writes the CSV log's tables byte for byte") {
  const fs::path dir = write_log("mcap_export", both(), 5000, 100);
  const CsvExportReport r = export_csv(dir / "flight.mcap", dir / "exported");
  CHECK(r.stopped == "");
  CHECK(r.skipped.empty());
  CHECK(r.rows.at("imu") == 5000);
  CHECK(r.rows.at("gnss") == 125);
  for (const char* t : {"imu.csv", "gnss.csv"}) {
    const std::string direct = read_file(dir / "topics" / t);
    CHECK(direct.size() > 1000);
    CHECK(read_file(dir / "exported" / t) == direct);
  }
  CHECK(read_file(dir / "topics" / "imu.csv").find("nan") != std::string::npos);  // the odd values are there
  CHECK(read_file(dir / "topics" / "imu.csv").find("-inf") != std::string::npos);
  CHECK_THROWS_WITH_AS(export_csv(dir / "flight.mcap", dir / "exported"), doctest::Contains("imu.csv: exists"), McapError);
  const fs::path not_mcap = write_file("not.mcap", "t [s],x\n");
  CHECK_THROWS_WITH_AS(export_csv(not_mcap, dir / "x"), doctest::Contains("not.mcap: not an MCAP file"), McapError);
}

TEST_CASE("mcap: log.zstd_level trades size for the writer's time; the messages are the same") {
  FlightLog::Format fast = both(), small = both();
  fast.mcap_zstd_level = -7;
  small.mcap_zstd_level = 19;
  const fs::path a = write_log("mcap_zstd_fast", fast, 3000, 0);
  const fs::path b = write_log("mcap_zstd_small", small, 3000, 0);
  CHECK(fs::file_size(a / "flight.mcap") > fs::file_size(b / "flight.mcap"));
  const std::vector<Logged> ma = messages_of(a / "flight.mcap"), mb = messages_of(b / "flight.mcap");
  CHECK(ma.size() == 3075);
  CHECK(ma == mb);
}

TEST_CASE("mcap: log.format mcap writes no topic table; csv writes no MCAP file") {
  const fs::path m = write_log("mcap_only", {false, true, 64 * 1024}, 100, 0);
  CHECK(fs::exists(m / "flight.mcap"));
  CHECK(!fs::exists(m / "topics"));
  CHECK(fs::exists(m / "params.csv"));
  const fs::path c = write_log("csv_only", {}, 100, 0);
  CHECK(!fs::exists(c / "flight.mcap"));
  CHECK(fs::exists(c / "topics" / "imu.csv"));
}

TEST_CASE("mcap: log.ros_channels false writes tern's own channels only") {
  // a stand-in for tern_dds's lookup: imu gets a ROS-typed copy
  set_ros_channel_lookup([](std::string_view topic, std::string_view) -> std::optional<RosChannel> {
    if (topic != "imu") return std::nullopt;
    return RosChannel{"/tern/imu/data", "test_msgs/msg/Stamp", "int64 stamp\n", [](const void* m, std::vector<std::string>& out) {
                        out.emplace_back(reinterpret_cast<const char*>(m), sizeof(Nanos));
                      }};
  });
  const auto count = [](const fs::path& dir, const std::string& topic) {
    std::size_t n = 0;
    for (const Logged& m : messages_of(dir / "flight.mcap")) n += m.topic == topic;
    return n;
  };
  const fs::path with = write_log("mcap_ros", {false, true, 64 * 1024, true}, 100, 0);
  const fs::path without = write_log("mcap_no_ros", {false, true, 64 * 1024, false}, 100, 0);
  set_ros_channel_lookup({});
  CHECK(count(with, "/tern/imu/data") == 100);
  CHECK(count(with, "/imu") == 100);
  CHECK(count(without, "/tern/imu/data") == 0);
  CHECK(count(without, "/imu") == 100);
  CHECK(count(without, "/gnss") == 3);
}

TEST_CASE("mcap: after a flush the open chunk is on disk, complete: a killed flight keeps it") {
  const fs::path dir = test_dir() / "mcap_open";
  FlightLog log(dir, {}, both(1024 * 1024));
  const auto imu = log.add_topic("imu", reflect::layout<msg::Imu>(), sizeof(msg::Imu), msg::Imu::type_name);
  for (int k = 0; k < 500; ++k) {
    const msg::Imu m = imu_at(k);
    log.capture(imu, m.stamp, &m);
  }
  log.flush();
  std::vector<Logged> seen;
  for (int i = 0; i < 200 && seen.size() < 500; ++i) {  // the writer thread writes it
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    const fs::path copy = test_dir() / "mcap_open_copy.mcap";
    fs::copy_file(dir / "flight.mcap", copy, fs::copy_options::overwrite_existing);
    const fs::path rec = test_dir() / "mcap_open_recovered.mcap";
    fs::remove(rec);
    recover_mcap(copy, rec, 1024 * 1024);
    seen = messages_of(rec);
  }
  CHECK(seen.size() == 500);
  log.close();
}

TEST_CASE("mcap: recover a file cut at many offsets: the messages of every complete chunk, in order") {
  const fs::path dir = write_log("mcap_cut", both(8 * 1024), 3000, 0);
  const fs::path whole = dir / "flight.mcap";
  const std::string bytes = read_file(whole);
  const auto all = messages_of(whole);
  // recovering a complete file gives it back unchanged
  recover_mcap(whole, dir / "same.mcap", 8 * 1024);
  CHECK(read_file(dir / "same.mcap") == bytes);
  // where the data section ends: a file cut after its data end record has lost only the summary
  std::size_t data_end = 0;
  {
    McapReader reader(whole);
    McapRecord record;
    while (reader.next(record)) {
    }
    REQUIRE(record.op == mcap::Op::data_end);
    data_end = record.offset + mcap::kRecordPrefix + record.content.size();
  }
  std::size_t previous = 0;
  int complete_chunks_seen = 0;
  for (std::size_t cut = 8; cut < bytes.size(); cut += bytes.size() / 37 + 1) {
    const fs::path part = dir / "part.mcap", out = dir / "recovered.mcap";
    std::ofstream(part, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(cut));
    fs::remove(out);
    if (cut < 8 + 9 + 16) {  // inside the header: not a readable file
      CHECK_THROWS_AS(recover_mcap(part, out, 8 * 1024), McapError);
      continue;
    }
    const RecoverReport r = recover_mcap(part, out, 8 * 1024);
    INFO("cut at ", cut, ": ", r.stopped);
    if (cut >= data_end)
      CHECK(r.stopped.empty());  // every message is there
    else
      CHECK(r.stopped.find("the file ends at byte " + std::to_string(cut)) == 0);
    std::string stopped = "?";
    const auto got = messages_of(out, nullptr, &stopped);
    CHECK(stopped == "");  // the recovered file is complete
    REQUIRE(got.size() <= all.size());
    CHECK(std::equal(got.begin(), got.end(), all.begin()));
    CHECK(got.size() >= previous);  // a longer file never recovers less
    CHECK(got.size() == r.messages);
    if (got.size() > previous) ++complete_chunks_seen;
    previous = got.size();
  }
  CHECK(complete_chunks_seen > 10);
  CHECK(previous > all.size() * 9 / 10);  // the last cut keeps almost everything
}
