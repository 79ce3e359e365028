// MAVLink FTP, read-only (core/apps/mavlink/mavlink_ftp.hpp), and the component metadata it serves
// (component_metadata.hpp), without a link.
#include <doctest/doctest.h>

#include <cstring>
#include <string>

#include <nlohmann/json.hpp>

#include "mavlink/component_metadata.hpp"
#include "mavlink/mavlink_ftp.hpp"

using namespace tern;
using namespace tern::core::mavlink;

namespace {

FtpPayload request(std::uint16_t seq, std::uint8_t opcode, std::uint8_t session = 0, std::uint32_t offset = 0, const std::string& path = "",
                   std::uint8_t size = 0) {
  FtpMessage m;
  m.seq = seq;
  m.opcode = opcode;
  m.session = session;
  m.offset = offset;
  std::memcpy(m.data.data(), path.data(), path.size());
  m.size = path.empty() ? size : static_cast<std::uint8_t>(path.size());
  return m.pack();
}

FtpMessage one(FtpServer& s, const FtpPayload& p) {
  const auto a = s.answer(p);
  REQUIRE(a.size() == 1);
  return FtpMessage::parse(a[0]);
}

std::uint32_t u32(const FtpMessage& m) {
  return m.data[0] | (m.data[1] << 8) | (m.data[2] << 16) | (static_cast<std::uint32_t>(m.data[3]) << 24);
}

}  // namespace

TEST_CASE("MAVLink FTP: open, read, burst read, the resend rule, and the errors a GCS meets") {
  std::string big(1000, '\0');
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<char>('a' + i % 26);
  FtpServer s({{"general.json", "{\"version\": 1}"}, {"big.bin", big}});

  const FtpMessage open = one(s, request(1, MAV_FTP_OPCODE_OPENFILERO, 0, 0, "/big.bin"));
  CHECK(open.opcode == MAV_FTP_OPCODE_ACK);
  CHECK(open.req_opcode == MAV_FTP_OPCODE_OPENFILERO);
  CHECK(open.seq == 2);
  CHECK(u32(open) == 1000);
  const std::uint8_t session = open.session;

  const FtpMessage read = one(s, request(2, MAV_FTP_OPCODE_READFILE, session, 950, "", 239));
  CHECK(read.opcode == MAV_FTP_OPCODE_ACK);
  CHECK(read.size == 50);
  CHECK(std::string(reinterpret_cast<const char*>(read.data.data()), 50) == big.substr(950));
  const FtpMessage eof = one(s, request(3, MAV_FTP_OPCODE_READFILE, session, 1000, "", 239));
  CHECK(eof.opcode == MAV_FTP_OPCODE_NAK);
  CHECK(eof.data[0] == MAV_FTP_ERR_EOF);
  // the same seq again: the same answer (the GCS lost ours)
  CHECK(FtpMessage::parse(s.answer(request(3, MAV_FTP_OPCODE_READFILE, session, 1000, "", 239))[0]).seq == eof.seq);

  const auto burst = s.answer(request(4, MAV_FTP_OPCODE_BURSTREADFILE, session, 0));
  REQUIRE(burst.size() == 5);  // 4 x 239 + 44
  std::string got;
  for (std::size_t k = 0; k < burst.size(); ++k) {
    const FtpMessage m = FtpMessage::parse(burst[k]);
    CHECK(m.seq == 5 + k);
    CHECK(m.burst_complete == (k + 1 == burst.size() ? 1 : 0));
    CHECK(m.offset == got.size());
    got.append(reinterpret_cast<const char*>(m.data.data()), m.size);
  }
  CHECK(got == big);

  CHECK(one(s, request(10, MAV_FTP_OPCODE_TERMINATESESSION, session)).opcode == MAV_FTP_OPCODE_ACK);
  CHECK(one(s, request(11, MAV_FTP_OPCODE_READFILE, session, 0, "", 10)).data[0] == MAV_FTP_ERR_INVALIDSESSION);
  CHECK(one(s, request(12, MAV_FTP_OPCODE_OPENFILERO, 0, 0, "nope.json")).data[0] == MAV_FTP_ERR_FILENOTFOUND);
  for (std::uint16_t k = 0; k < FtpServer::kMaxSessions; ++k)
    CHECK(one(s, request(static_cast<std::uint16_t>(20 + k), MAV_FTP_OPCODE_OPENFILERO, 0, 0, "general.json")).opcode ==
          MAV_FTP_OPCODE_ACK);
  CHECK(one(s, request(30, MAV_FTP_OPCODE_OPENFILERO, 0, 0, "general.json")).data[0] == MAV_FTP_ERR_NOSESSIONSAVAILABLE);
  CHECK(one(s, request(31, MAV_FTP_OPCODE_RESETSESSION)).opcode == MAV_FTP_OPCODE_ACK);
  CHECK(one(s, request(32, 7 /* WriteFile */)).data[0] == MAV_FTP_ERR_UNKNOWNCOMMAND);
  CHECK(one(s, request(33, MAV_FTP_OPCODE_READFILE, 200)).data[0] == MAV_FTP_ERR_INVALIDSESSION);  // no such session id
  CHECK(one(s, request(34, MAV_FTP_OPCODE_OPENFILERO, 0, 0, "", 250)).data[0] == MAV_FTP_ERR_INVALIDDATASIZE);

  const FtpMessage list = one(s, request(40, MAV_FTP_OPCODE_LISTDIRECTORY, 0, 0, "/"));
  CHECK(list.opcode == MAV_FTP_OPCODE_ACK);
  CHECK(std::string(reinterpret_cast<const char*>(list.data.data())) == "Fbig.bin\t1000");
  CHECK(one(s, request(41, MAV_FTP_OPCODE_LISTDIRECTORY, 0, 2, "/")).data[0] == MAV_FTP_ERR_EOF);
}

namespace {
struct Real : ParamBase {
  Real() : ParamBase(ParamKind::real, 0.5) {}
  ParamValue value() const override { return 0.5; }
  void assign(const ParamValue&) override {}
};
struct Flag : ParamBase {
  Flag() : ParamBase(ParamKind::boolean, true) {}
  ParamValue value() const override { return true; }
  void assign(const ParamValue&) override {}
};
}  // namespace

TEST_CASE("component metadata: every MAVLink parameter described under its id, in the schemas' shape") {
  Real kp;
  kp.set_identity("roll_kp", "slc.roll_kp", ParamSpec("", 0.0, 10.0, "roll angle gain"), 0.5);
  Real alt;
  alt.set_identity("init_altitude", "sim.init_altitude", ParamSpec("m", 0, 1000, "initial altitude").start_only(), 0.5);
  Flag wind;
  wind.set_identity("wind_enabled_with_a_long_name", "sim.wind_enabled_with_a_long_name", ParamSpec("", 0, 1, "wind on"), true);
  const std::vector<std::pair<std::string, const ParamBase*>> params{
      {"slc.roll_kp", &kp}, {"sim.init_altitude", &alt}, {"sim.wind_enabled_with_a_long_name", &wind}};
  const ParamTable table({{"slc.roll_kp", ParamKind::real},
                          {"sim.init_altitude", ParamKind::real},
                          {"sim.wind_enabled_with_a_long_name", ParamKind::boolean}});
  const MetadataFiles m = component_metadata(table, params);
  const auto general = nlohmann::json::parse(m.general);
  CHECK(general["version"] == 1);
  REQUIRE(general["metadataTypes"].size() == 1);
  CHECK(general["metadataTypes"][0]["type"] == COMP_METADATA_TYPE_PARAMETER);
  CHECK(general["metadataTypes"][0]["uri"] == "mftp://parameters.json");
  const auto p = nlohmann::json::parse(m.parameters);
  CHECK(p["version"] == 3);
  REQUIRE(p["parameters"].size() == 3);
  for (std::size_t i = 0; i < 3; ++i) CHECK(p["parameters"][i]["name"] == table.params()[i].id);
  CHECK(p["parameters"][0]["shortDesc"] == "roll angle gain");
  CHECK(p["parameters"][0]["type"] == "Float");
  CHECK(p["parameters"][0]["min"] == 0.0);
  CHECK(p["parameters"][0]["max"] == 10.0);
  CHECK(p["parameters"][0]["group"] == "slc");
  CHECK(p["parameters"][1]["units"] == "m");
  CHECK(p["parameters"][1]["rebootRequired"] == true);
  CHECK(p["parameters"][2]["type"] == "Int32");
  CHECK(p["parameters"][2]["name"].get<std::string>().size() <= 16);
  CHECK(p["parameters"][2]["longDesc"] == "tern parameter sim.wind_enabled_with_a_long_name");
}
