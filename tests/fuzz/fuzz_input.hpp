// tests/fuzz/fuzz_input.hpp: the fuzzer's bytes as a file, for the readers that take a path (the MCAP
// reader, the CSV tables, the YAML loaders): one file per fuzzing process, rewritten for each input,
// in TMPDIR (as_file) or in a directory of its own there (in_dir: for a reader that takes a
// directory and a fixed name, or resolves relative paths against the file's directory).
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace tern::fuzz {

/// A path of this process's, removed (with what it holds) when the process exits normally.
struct Scratch {
  std::filesystem::path path;
  ~Scratch() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

/// Writes `data` to this process's input file (in TMPDIR) and returns its path.
inline std::filesystem::path as_file(const std::uint8_t* data, std::size_t size, const char* extension) {
  static const Scratch scratch{std::filesystem::temp_directory_path() / ("tern-fuzz-" + std::to_string(::getpid()) + extension)};
  const std::filesystem::path& file = scratch.path;
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return file;
}

/// The error an input was refused with, on stderr when TERN_FUZZ_VERBOSE is set (to see what a
/// seed or a crash reproducer runs into: `TERN_FUZZ_VERBOSE=1 build-fuzz/bin/<target> FILE`).
inline void note(const std::exception& e) {
  static const bool verbose = std::getenv("TERN_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "refused: %s\n", e.what());
}

/// Writes `data` to `name` in this process's own directory (TMPDIR/tern-fuzz-<pid>.d, created)
/// and returns the file's path.
inline std::filesystem::path in_dir(const std::uint8_t* data, std::size_t size, const char* name) {
  static const Scratch scratch{[] {
    auto d = std::filesystem::temp_directory_path() / ("tern-fuzz-" + std::to_string(::getpid()) + ".d");
    std::filesystem::create_directories(d);
    return d;
  }()};
  const std::filesystem::path& dir = scratch.path;
  const auto file = dir / name;
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return file;
}

}  // namespace tern::fuzz
