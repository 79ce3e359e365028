// Reading a file someone hands tern, and echoing it (tern/input_file.hpp).
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <yaml-cpp/yaml.h>

#include "tern/input_file.hpp"
#include "tern/yaml_keys.hpp"

using namespace tern;

namespace {
std::string error_of_yaml(const std::filesystem::path& file) {
  try {
    load_yaml_file(file, "test file");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("input file: only a regular file of bounded size is read") {
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  CHECK(input_file_problem(dir, kMaxTextFileBytes) == "is a directory");
  CHECK(input_file_problem("/dev/zero", kMaxTextFileBytes) == "is not a regular file (a character device)");
  CHECK(input_file_problem(dir / "tern-no-such-file", kMaxTextFileBytes) == "does not exist");
  const std::filesystem::path f = dir / "tern_sdk_test_input.yaml";
  std::ofstream(f) << "a: 1\n";
  CHECK(input_file_problem(f, kMaxTextFileBytes) == "");
  CHECK(input_file_problem(f, 4) == "is 5 bytes, more than the 4 bytes tern reads of one");
  CHECK_THROWS_WITH_AS(read_text_file(f, "test file", 4),
                       (f.string() + ": test file is 5 bytes, more than the 4 bytes tern reads of one").c_str(), std::runtime_error);
  CHECK(read_text_file(f, "test file") == "a: 1\n");
  std::filesystem::remove(f);
}

TEST_CASE("input file: a YAML alias bomb is refused before anything walks it, a syntax error names the file") {
  const std::filesystem::path f = std::filesystem::temp_directory_path() / "tern_sdk_test_bomb.yaml";
  std::string text = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int k = 1; k <= 5; ++k) {
    text += "a" + std::to_string(k) + ": &a" + std::to_string(k) + " [";
    for (int i = 0; i < 10; ++i) {
      text += i ? ", *a" : "*a";
      text += std::to_string(k - 1);
    }
    text += "]\n";
  }
  std::ofstream(f) << text;  // 10^6 nodes once expanded
  CHECK(error_of_yaml(f) == f.string() + ": more than 100000 YAML nodes once its aliases are expanded (an alias bomb?)");
  std::ofstream(f) << "a: [1, 2\n";
  const std::string syntax = error_of_yaml(f);
  CHECK(syntax.rfind(f.string() + ":", 0) == 0);
  CHECK(syntax.find(": YAML syntax error: ") != std::string::npos);
  std::ofstream(f) << "a: &a [1, 2]\nb: [*a, *a]\n";  // aliases within the bound: read
  CHECK(error_of_yaml(f) == "");
  std::ofstream(f) << "a: " + std::string(5000, '[') + std::string(5000, ']') + "\n";  // yaml-cpp's own words: "bad file"
  const std::string deep = error_of_yaml(f);
  CHECK(deep.rfind(f.string() + ":1:", 0) == 0);
  CHECK(deep.find(": YAML nested too deeply") != std::string::npos);
  std::filesystem::remove(f);
}

TEST_CASE("printable: control characters and bytes of no UTF-8 character escaped, long text cut") {
  CHECK(printable("plain name") == "plain name");
  CHECK(printable("\x1b[31mred\x07\n") == "\\x1b[31mred\\x07\\n");
  CHECK(printable("\xc2\x9b"
                  "2J") == "\\x9b2J");                                                   // U+009B, the C1 CSI
  CHECK(printable("caf\xc3\xa9") == "caf\xc3\xa9");                                      // UTF-8 letters kept
  CHECK(printable("\xe2\x82\xac \xf0\x9f\x9b\xa9") == "\xe2\x82\xac \xf0\x9f\x9b\xa9");  // 3- and 4-byte characters kept
  // bytes of no UTF-8 character: a lone 0x9b (CSI to a terminal of 8-bit controls), a stray
  // continuation byte, a lead byte cut short, 0xff
  CHECK(printable("\x9b"
                  "2J") == "\\x9b2J");
  CHECK(printable("a\x8a\xc3") == "a\\x8a\\xc3");
  CHECK(printable("\xe2\x82z\xff") == "\\xe2\\x82z\\xff");
  CHECK(printable("\xc3\xa9\xc3\xa9\xc3\xa9", 2) == "\xc3\xa9\xc3\xa9...");  // characters counted, not bytes
  CHECK(printable(std::string(300, 'a')) == std::string(200, 'a') + "...");
}

TEST_CASE("repeated_key: the first key a map gives twice, where it stands first and again") {
  const auto r = tern::repeated_key(YAML::Load("a: 1\nb: 2\n[x]: 3\nb: 4\na: 5\n"));
  REQUIRE(r.has_value());
  CHECK(r->key == "b");  // the first repeat, b on line 4; a list as a key is skipped
  CHECK(r->first.line == 1);
  CHECK(r->again.line == 3);
  CHECK_FALSE(tern::repeated_key(YAML::Load("a: 1\nb: 2\n")).has_value());
  CHECK_FALSE(tern::repeated_key(YAML::Load("[a, a]")).has_value());  // no map
}
