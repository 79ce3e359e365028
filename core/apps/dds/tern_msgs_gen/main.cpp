// core/apps/dds/tern_msgs_gen/main.cpp: tern_msgs_gen OUT_DIR, run by core/apps/dds/CMakeLists.txt
// at build time. Writes, from the SDK structs' describe() and wire_spec.hpp:
//   OUT_DIR/idl/tern_msgs/msg/<file>.idl     the IDL fastddsgen compiles (write_idl.hpp)
//   OUT_DIR/src/tern_msgs_convert.{hpp,cpp}  the conversions tern_dds compiles (write_convert.hpp)
// A file whose text is unchanged is not rewritten (what depends on it is not rebuilt).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

#include "wire_spec.hpp"
#include "write_convert.hpp"
#include "write_idl.hpp"

namespace fs = std::filesystem;
using namespace tern::msgs_gen;

namespace {

struct Collect {
  std::vector<WireStruct>* out;
  template <class M>
  void message(const WireSpec& spec) {
    out->push_back(wire_struct<M>(spec));
  }
};

void write_if_changed(const fs::path& path, const std::string& text) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream old;
  old << in.rdbuf();
  if (in && old.str() == text) return;
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: tern_msgs_gen OUT_DIR\n";
    return 2;
  }
  try {
    const fs::path out = argv[1];
    std::vector<WireStruct> all;
    Collect c{&all};
    tern_msgs_messages(c);
    std::set<std::string> files;
    for (const auto& s : all) files.insert(std::string(s.spec.file));
    for (const auto& f : files) write_if_changed(out / "idl/tern_msgs/msg" / (f + ".idl"), idl_file(f, all));
    write_if_changed(out / "src/tern_msgs_convert.hpp", convert_header(all));
    write_if_changed(out / "src/tern_msgs_convert.cpp", convert_source(all));
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
  return 0;
}
