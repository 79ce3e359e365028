// tests/fuzz/fuzz_input.hpp: the fuzzer's bytes as a file, for the readers that take a path (the MCAP
// reader, the CSV tables): one file per fuzzing process, rewritten for each input.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace tern::fuzz {

/// Writes `data` to this process's input file (in TMPDIR) and returns its path.
inline std::filesystem::path as_file(const std::uint8_t* data, std::size_t size, const char* extension) {
  static const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("tern-fuzz-" + std::to_string(::getpid()) + extension);
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return file;
}

}  // namespace tern::fuzz
