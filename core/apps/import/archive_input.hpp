// core/apps/import/archive_input.hpp: `tern import`'s INPUT as a directory: a directory as it is,
// an archive as shipped (.zip, .tar.gz, .tgz, .tar.bz2, .tar.xz, .tar: read by libarchive's zip and
// tar readers, whatever the name says) unpacked into a fresh temporary directory that is removed
// again when the ArchiveInput goes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace tern::core {

/// What an archive may unpack to (docs/hostile-inputs.md); more is an ImportError and the
/// temporary directory is removed.
struct ArchiveLimits {
  /// bytes: all members together (a zip bomb stops here; a flight log is far smaller)
  std::uint64_t max_bytes = std::uint64_t{4} << 30;
  /// the most members an archive may hold
  std::size_t max_members = 100'000;
};

class ArchiveInput {
 public:
  /// Throws ImportError naming the archive (and the member) if it cannot be read or unpacked
  /// within `limits`.
  explicit ArchiveInput(const std::filesystem::path& input, const ArchiveLimits& limits = {});
  ~ArchiveInput();
  ArchiveInput(const ArchiveInput&) = delete;
  ArchiveInput& operator=(const ArchiveInput&) = delete;

  /// The directory to import from.
  const std::filesystem::path& dir() const { return dir_; }
  /// `text` (an error or a warning) with the temporary directory's path replaced by the
  /// archive's: "px4.zip:GPS.txt:121: ..." rather than "/tmp/tern-import-XXXXXX/GPS.txt:121: ...".
  std::string readable(std::string text) const;

 private:
  std::filesystem::path dir_;
  std::filesystem::path input_;
  std::filesystem::path temp_;  // "" for a directory input
};

}  // namespace tern::core
