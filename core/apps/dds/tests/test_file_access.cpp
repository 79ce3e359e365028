// FileAccess: the files a network request may read or write on the vehicle (issue 20, item 3:
// `tern mission load ../../../../etc/shadow` was read, `tern param save /any/path` overwrote).
#include <doctest/doctest.h>

#include <fstream>

#include "dds_bridge.hpp"
#include "file_access.hpp"
#include "test_util.hpp"

using tern::core::DdsError;
using tern::core::ddsi::FileAccess;

namespace {
std::string refusal(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const DdsError& e) {
    return e.what();
  }
  return "(accepted)";
}
}  // namespace

TEST_CASE("file access: names inside the allowed directories resolve; everything else gets one refusal line") {
  const fs::path root = test_dir() / "fa";
  fs::create_directories(root / "missions" / "sub");
  fs::create_directories(root / "extra");
  fs::create_directories(root / "outside");
  std::ofstream(root / "missions" / "m.yaml") << "waypoints: []\n";
  std::ofstream(root / "missions" / "sub" / "n.yml") << "waypoints: []\n";
  std::ofstream(root / "extra" / "e.yaml") << "waypoints: []\n";
  std::ofstream(root / "outside" / "secret.yaml") << "password: hunter2\n";
  fs::create_symlink(root / "outside" / "secret.yaml", root / "missions" / "link.yaml");
  const FileAccess fa({root / "missions", root / "extra"});
  const std::string rq = "load_mission_from_file";
  auto read = [&](const std::string& n) { return refusal([&] { fa.for_reading(rq, n); }); };

  CHECK(fa.for_reading(rq, "m.yaml") == root / "missions" / "m.yaml");
  CHECK(fa.for_reading(rq, "sub/n.yml") == root / "missions" / "sub" / "n.yml");
  CHECK(fa.for_reading(rq, (root / "extra" / "e.yaml").string()) == root / "extra" / "e.yaml");
  CHECK(read("../../../../etc/shadow") ==
        "load_mission_from_file: refused '../../../../etc/shadow': '..' is not allowed (name a file inside " +
            (root / "missions").string() + ", " + (root / "extra").string() + ")");
  CHECK(read("sub/../m.yaml").find("'..' is not allowed") != std::string::npos);
  CHECK(read("/etc/shadow") == "load_mission_from_file: refused '/etc/shadow': only .yaml or .yml files");
  CHECK(read((root / "outside" / "secret.yaml").string()) ==
        "load_mission_from_file: refused '" + (root / "outside" / "secret.yaml").string() + "': outside the allowed directories (" +
            (root / "missions").string() + ", " + (root / "extra").string() + ")");
  // a symbolic link inside leads outside: refused, and nothing of the file is in the message
  const std::string link = read("link.yaml");
  CHECK(link.find("outside the allowed directories") != std::string::npos);
  CHECK(link.find("hunter2") == std::string::npos);
  CHECK(read("") == "load_mission_from_file: refused: no file name");
  CHECK(read("a\nb.yaml") == "load_mission_from_file: refused 'a?b.yaml': control characters are not allowed in a file name");
  CHECK(read("none.yaml") == "load_mission_from_file: no such file on the vehicle: " + (root / "missions" / "none.yaml").string());
  CHECK(refusal([] { FileAccess({}).for_reading("load_mission_from_file", "m.yaml"); }) ==
        "load_mission_from_file: refused 'm.yaml': this vehicle allows no directory for it");
}

TEST_CASE("file access: writing refuses an existing file unless asked to overwrite it") {
  const fs::path root = test_dir() / "fa_write";
  fs::create_directories(root);
  const FileAccess fa({root});
  CHECK(fa.for_writing("param_save", "p.yaml", false) == root / "p.yaml");
  std::ofstream(root / "p.yaml") << "x: 1\n";
  CHECK(refusal([&] { fa.for_writing("param_save", "p.yaml", false); }) ==
        "param_save: refused: " + (root / "p.yaml").string() + " exists (ask to overwrite it: --overwrite)");
  CHECK(fa.for_writing("param_save", "p.yaml", true) == root / "p.yaml");
  CHECK(refusal([&] { fa.for_writing("param_save", "/etc/passwd.yaml", true); }).find("outside the allowed directories") !=
        std::string::npos);
  CHECK(refusal([&] { fa.for_writing("param_save", "nodir/p.yaml", false); }) ==
        "param_save: no such directory on the vehicle: " + (root / "nodir").string());
}

TEST_CASE("file access: the write itself refuses a file or link that appeared after the check") {
  const fs::path root = test_dir() / "fa_race";
  fs::remove_all(root);
  fs::create_directories(root / "outside");
  const FileAccess fa({root});
  const fs::path p = fa.for_writing("param_save", "p.yaml", false);
  std::ofstream(p) << "x: 1\n";  // appeared between the check and the write
  CHECK(refusal([&] { FileAccess::write_file("param_save", p, "y: 2\n", false); }) ==
        "param_save: refused: " + p.string() + " exists (ask to overwrite it: --overwrite)");
  FileAccess::write_file("param_save", p, "y: 2\n", true);
  std::ifstream in(p);
  CHECK(std::string(std::istreambuf_iterator<char>(in), {}) == "y: 2\n");
  const fs::path q = root / "q.yaml";
  fs::create_symlink(root / "outside" / "target.yaml", q);  // a link planted after the check
  CHECK(refusal([&] { FileAccess::write_file("param_save", q, "z: 3\n", true); }) ==
        "param_save: refused: " + q.string() + " is a symbolic link");
  CHECK(!fs::exists(root / "outside" / "target.yaml"));
}
