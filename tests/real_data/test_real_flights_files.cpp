// The two real flights ship with the repository (data/real_flights, issue 63): each file is there,
// byte for byte the one its authors published (SHA-256 and size as data/real_flights/README.md
// records them), with its licence text; README.md and SHA256SUMS list the same checksums as this
// test. ctest runs these cases alone as `real_flights_files`.
#include <doctest/doctest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "graph/loader.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kDir = fs::path(TERN_REAL_FLIGHTS_DIR);

struct Shipped {
  const char* name;
  std::uintmax_t bytes;
  const char* sha256;  ///< lower-case hex, as sha256sum prints it
  const char* licence;
};

// The zip is InertialNav's code/InputFilesPX4_search.zip at 037c5c3a; the tar.gz holds 12 CSVs of
// castacks/alfa-dataset-tools alfa-cpp/csv/ at 8f8c0343 (data/real_flights/README.md).
constexpr Shipped kFlights[] = {
    {"px4_fixedwing_zurich2014_InputFilesPX4_search.zip", 1565717, "46b757e8b01701313847e1c91b5afd2311ed385d257df82a26bb48d48e1acce1",
     "LICENSE-InertialNav.txt"},
    {"alfa_carbonZ_2018-07-18-15-53-31_1_engine_failure_csv.tar.gz", 326242,
     "eb542ea832037597d727c5b32681b2b3b8707620277ceb3a099b88a8f1c6c1e8", "LICENSE-alfa-dataset-tools.txt"},
};

std::string text_of(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST_SUITE("real_flights_files") {
  TEST_CASE("data/real_flights: both real flights are there, unchanged (size and SHA-256 as published)") {
    for (const Shipped& f : kFlights) {
      const fs::path p = kDir / f.name;
      INFO(p.string());
      REQUIRE_MESSAGE(fs::exists(p), "missing: the real flights ship with the repository (data/real_flights/README.md)");
      CHECK(fs::file_size(p) == f.bytes);
      CHECK_MESSAGE(tern::core::file_sha256(p) == f.sha256, "changed: these files are kept byte for byte as their authors published them");
    }
  }

  TEST_CASE("data/real_flights: README.md and SHA256SUMS list the same checksums; the licence texts are there") {
    const std::string readme = text_of(kDir / "README.md");
    const std::string sums = text_of(kDir / "SHA256SUMS");
    for (const Shipped& f : kFlights) {
      INFO(f.name);
      CHECK(readme.find(f.sha256) != std::string::npos);
      CHECK(sums.find(std::string(f.sha256) + "  " + f.name + "\n") != std::string::npos);  // `sha256sum -c SHA256SUMS`
      const std::string licence = text_of(kDir / f.licence);
      CHECK(licence.find("Redistribution and use in source and binary forms") != std::string::npos);
      CHECK(readme.find(f.licence) != std::string::npos);
    }
    CHECK(text_of(kDir / "LICENSE-InertialNav.txt").find("Copyright (c) 2014, Paul Riseborough") != std::string::npos);
    CHECK(text_of(kDir / "LICENSE-alfa-dataset-tools.txt").find("Copyright (c) 2019, Carnegie Mellon University") != std::string::npos);
    CHECK(readme.find("doi:10.1177/0278364920966642") != std::string::npos);  // the citation ALFA's authors ask for
  }
}
