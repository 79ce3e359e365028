// fuzz_archive: libFuzzer target for `tern import`'s archive extraction (core/apps/import/
// archive_input.hpp ArchiveInput, libarchive): the bytes as an archive as shipped (.zip, .tar.gz,
// .tgz, .tar: libarchive tells them apart by content) unpacked into a fresh temporary directory,
// within limits lowered for the fuzzer (16 MiB, 1000 members; `tern import`'s are 4 GiB and
// 100 000). Any bytes: an unpacked tree of regular files and directories only (no symlink, hard
// link, device or FIFO materialised), inside the temporary directory, at most the limit's bytes
// (files' apparent sizes: a sparse member counts whole) and members, every directory the user's
// to enter and empty (owner rwx) and every file the user's to read; or one ImportError line
// naming the archive. Nothing is written outside the temporary directory, and the directory is
// gone once the ArchiveInput is: this process's TMPDIR (TMPDIR/tern-fuzz-<pid>.archive/tmp) is
// empty after every input, and its parent holds nothing but the input file. Never a crash, a hang
// or another exception.
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_input.hpp"
#include "import/archive_input.hpp"
#include "import/sensor_log_writer.hpp"

using namespace tern::core;
namespace fs = std::filesystem;

namespace {

constexpr ArchiveLimits kLimits{std::uint64_t{16} << 20, 1000};

struct Place {
  fs::path base, tmp, input;
};

/// This process's directory: the input file, and the TMPDIR ArchiveInput makes its directory in.
const Place& place() {
  static const tern::fuzz::Scratch scratch{[] {
    const fs::path base = fs::temp_directory_path() / ("tern-fuzz-" + std::to_string(::getpid()) + ".archive");
    fs::create_directories(base / "tmp");
    ::setenv("TMPDIR", (base / "tmp").c_str(), 1);
    return base;
  }()};
  static const Place p{scratch.path, scratch.path / "tmp", scratch.path / "input"};
  return p;
}

/// The unpacked tree: regular files and directories only, the user's to read and remove, within the limits.
void check_tree(const fs::path& dir) {
  std::uint64_t bytes = 0;
  std::size_t files = 0;
  for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator(); ++it) {
    struct stat st {};
    if (::lstat(it->path().c_str(), &st) != 0) __builtin_trap();
    if (S_ISDIR(st.st_mode)) {
      if ((st.st_mode & S_IRWXU) != S_IRWXU) __builtin_trap();  // a directory the user could not empty
    } else if (S_ISREG(st.st_mode)) {
      if ((st.st_mode & S_IRUSR) == 0 || st.st_nlink != 1) __builtin_trap();  // unreadable, or a hard link
      bytes += static_cast<std::uint64_t>(st.st_size);
      ++files;
    } else {
      __builtin_trap();  // a symlink, a device, a FIFO or a socket
    }
  }
  if (bytes > kLimits.max_bytes || files > kLimits.max_members) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Place& p = place();
  std::ofstream(p.input, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  try {
    const ArchiveInput a(p.input, kLimits);
    if (a.dir().parent_path() != p.tmp) __builtin_trap();  // a fresh directory in TMPDIR
    check_tree(a.dir());
  } catch (const ImportError& e) {
    tern::fuzz::note(e);
    const std::string what = e.what();
    if (what.rfind(p.input.string() + ":", 0) != 0 || what.find('\n') != std::string::npos) __builtin_trap();
  }
  // nothing left behind, nothing written beside
  if (!fs::is_empty(p.tmp)) __builtin_trap();
  for (const auto& e : fs::directory_iterator(p.base))
    if (e.path() != p.tmp && e.path() != p.input) __builtin_trap();
  return 0;
}
