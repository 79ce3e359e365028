// A shared object that cannot be loaded is one line naming the file and what is wrong, never a
// signal (issue 19, item 4): dlopen of a truncated file raises SIGBUS, which would end this test
// process. The broken files are made here from a good test plugin.
#include <doctest/doctest.h>
#include <elf.h>

#include <fstream>

#include "graph/loader.hpp"
#include "test_util.hpp"

namespace {

const fs::path kGood = fs::path(TERN_TEST_PLUGIN_DIR) / "libtern_test_null.so";
const fs::path kController = fs::path(TERN_TEST_PLUGIN_DIR) / "libtern_test_controller.so";

/// A copy of `from` named `name` in the test directory, cut to `size` bytes (all if npos), with
/// `patch` written at `offset`.
fs::path broken(const std::string& name, const fs::path& from, std::size_t size, std::size_t offset = 0, const std::string& patch = "") {
  std::string bytes = read_file(from);
  bytes.resize(std::min(size, bytes.size()));
  bytes.replace(offset, patch.size(), patch);
  return write_file(name, bytes);
}

std::string load_error(const fs::path& so) {
  try {
    tern::core::open_plugin(so);
  } catch (const tern::core::ConfigError& e) {
    return e.what();
  }
  return "";
}

std::string le16(std::uint16_t v) { return {static_cast<char>(v & 0xff), static_cast<char>(v >> 8)}; }

/// e_machine of an architecture this host is not.
std::string foreign_machine() {
#if defined(__x86_64__)
  return le16(EM_AARCH64);
#else
  return le16(EM_X86_64);
#endif
}

}  // namespace

TEST_CASE("truncated, empty, foreign or non-ELF shared objects: one line naming the file, no signal") {
  const std::size_t n = fs::file_size(kGood);
  const fs::path half = broken("libtern_half.so", kGood, n / 2);
  CHECK(load_error(half).find("cannot load '" + half.string() + "': truncated: its loadable segments end at byte ") == 0);
  const fs::path tail = broken("libtern_tail.so", kGood, n - 100);
  CHECK(load_error(tail).find("cannot load '" + tail.string() + "': truncated: its section headers end at byte " + std::to_string(n) +
                              ", the file has " + std::to_string(n - 100) + " bytes") == 0);
  const fs::path empty = write_file("libtern_empty.so", "");
  CHECK(load_error(empty) == "cannot load '" + empty.string() + "': empty file (0 bytes)");
  const fs::path head = broken("libtern_head.so", kGood, 40);
  CHECK(load_error(head) == "cannot load '" + head.string() + "': truncated: 40 bytes, less than an ELF header (64 bytes)");
  const fs::path text = write_file("libtern_text.so", "INPUT(libfoo.so)\n");
  CHECK(load_error(text) == "cannot load '" + text.string() + "': not an ELF file (17 bytes)");
  const fs::path arm = broken("libtern_arm.so", kGood, n, offsetof(Elf64_Ehdr, e_machine), foreign_machine());
  CHECK(load_error(arm).find("cannot load '" + arm.string() + "': built for ") == 0);
  CHECK(load_error(arm).find(", this host is ") != std::string::npos);
  const fs::path c32 = broken("libtern_32.so", kGood, n, EI_CLASS, std::string(1, ELFCLASS32));
  CHECK(load_error(c32) == "cannot load '" + c32.string() + "': a 32-bit ELF file; this host loads 64-bit shared objects");
  const fs::path exec = broken("libtern_exec.so", kGood, n, offsetof(Elf64_Ehdr, e_type), le16(ET_EXEC));
  CHECK(load_error(exec) == "cannot load '" + exec.string() + "': an executable (ET_EXEC), not a shared object (ET_DYN)");
  CHECK(load_error(kGood) == "");
}

TEST_CASE("a truncated plugin named in a config is one line with file, line and field") {
  const fs::path half = broken("libtern_cfg_half.so", kGood, fs::file_size(kGood) / 2);
  const std::string e = build_error(base_config("  - {name: x, plugin: " + half.string() + ", rate: 400}\n"));
  CHECK(e.find(":9:23: plugins[3].plugin: cannot load '" + half.string() + "': truncated: ") != std::string::npos);
}

TEST_CASE("a bad swap is refused, the old plugin flies on, and no temporary file is left") {
  const auto swap_dirs = [] {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(fs::temp_directory_path()))
      n += e.path().filename().string().rfind("tern-swap-" + std::to_string(::getpid()) + "-", 0) == 0;
    return n;
  };
  tern::core::HostOptions o;
  o.quiet = true;
  o.log_dir = test_dir() / "bad_swap";
  tern::core::Host h(tern::core::load_config(write_file("bad_swap.yaml", base_config())), o);
  h.build();
  const std::size_t dirs_before = swap_dirs();
  const fs::path half = broken("libtern_swap_half.so", kController, fs::file_size(kController) / 2);
  const auto swap_error = [&](const fs::path& so) {
    try {
      h.swap("ctl", so);
    } catch (const tern::core::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(swap_error(half).find("swap ctl <- " + half.string() + " refused, 'test_controller' keeps flying: cannot load '" + half.string() +
                              "': truncated: ") == 0);
  const fs::path arm =
      broken("libtern_swap_arm.so", kController, fs::file_size(kController), offsetof(Elf64_Ehdr, e_machine), foreign_machine());
  CHECK(swap_error(arm).find("keeps flying: cannot load '" + arm.string() + "': built for ") != std::string::npos);
  CHECK(swap_dirs() == dirs_before);
  CHECK(h.fly().ok);
}
