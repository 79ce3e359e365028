#include "import/archive_input.hpp"

#include <archive.h>
#include <archive_entry.h>
#include <stdlib.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "import/sensor_log_writer.hpp"
#include "tern/input_file.hpp"

namespace tern::core {

namespace fs = std::filesystem;

namespace {

using Reader = std::unique_ptr<archive, decltype(&archive_read_free)>;
using Writer = std::unique_ptr<archive, decltype(&archive_write_free)>;

/// libarchive's error text of `a`, for one line (it may have none).
std::string error_text(archive* a) {
  const char* e = archive_error_string(a);
  return e ? printable(e) : std::string("error ") + std::to_string(archive_errno(a));
}

fs::path make_temp_dir() {
  std::string pattern = (fs::temp_directory_path() / "tern-import-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) throw ImportError(fmt::format("cannot create a temporary directory ({})", pattern));
  return pattern;
}

[[noreturn]] void too_large(const fs::path& file, const std::string& member, std::uint64_t max_bytes) {
  throw ImportError(fmt::format("{}: {}: the archive unpacks to more than {} bytes (docs/hostile-inputs.md)", file.string(),
                                printable(member), max_bytes));
}

/// Copies the current member's data from `in` to the disk writer `out`. `total`: the bytes the
/// members before this one take on disk (their sizes: a sparse member's holes count); at most
/// `max_bytes` with this member's data, a zip bomb stops there. A data block's end, not its size,
/// counts: a block written at an offset past the member's end leaves a hole that counts too.
void copy_data(archive* in, archive* out, const fs::path& file, const std::string& member, std::uint64_t total, std::uint64_t max_bytes) {
  const void* buf = nullptr;
  size_t size = 0;
  la_int64_t offset = 0;
  for (;;) {
    const int r = archive_read_data_block(in, &buf, &size, &offset);
    if (r == ARCHIVE_EOF) return;
    if (r < ARCHIVE_OK) throw ImportError(fmt::format("{}: {}: {}", file.string(), printable(member), error_text(in)));
    if (offset < 0 || static_cast<std::uint64_t>(offset) > max_bytes || size > max_bytes - static_cast<std::uint64_t>(offset) ||
        total > max_bytes - static_cast<std::uint64_t>(offset) - size)
      too_large(file, member, max_bytes);
    if (archive_write_data_block(out, buf, size, offset) < ARCHIVE_OK)
      throw ImportError(fmt::format("{}: {}: {}", file.string(), printable(member), error_text(out)));
  }
}

/// "" for a member tern unpacks (a regular file or a directory), else what it is: a symlink (its
/// target would be read in the member's place: a file outside the archive, /dev/zero, or another
/// member standing in for the one named), a hard link, a device, a FIFO, a socket.
std::string member_kind_problem(archive_entry* entry) {
  if (const char* target = archive_entry_symlink(entry)) return fmt::format("is a symlink (to '{}')", printable(target));
  if (const char* target = archive_entry_hardlink(entry)) return fmt::format("is a hard link (to '{}')", printable(target));
  const mode_t type = archive_entry_filetype(entry);
  if (type == AE_IFREG || type == AE_IFDIR) return "";
  return type == AE_IFLNK ? "is a symlink" : type == AE_IFCHR || type == AE_IFBLK ? "is a device" : "is not a regular file";
}

/// A relative member name without "..".
bool safe_member(const std::string& member) {
  const fs::path p(member);
  if (member.empty() || p.is_absolute()) return false;
  for (const auto& part : p)
    if (part == "..") return false;
  return true;
}

void unpack(const fs::path& file, const fs::path& into, const ArchiveLimits& limits) {
  Reader in(archive_read_new(), archive_read_free);
  // the formats tern import documents (a flight log's archive as shipped: .zip, .tar with gzip,
  // bzip2 or xz), not libarchive's all: its mtree format is a listing that names files of this
  // machine as the members' contents (mtree(5): contents=), and some of its filters run an
  // external program
  archive_read_support_format_zip(in.get());
  archive_read_support_format_tar(in.get());
  archive_read_support_filter_gzip(in.get());
  archive_read_support_filter_bzip2(in.get());
  archive_read_support_filter_xz(in.get());
  if (archive_read_open_filename(in.get(), file.c_str(), 1 << 16) != ARCHIVE_OK)
    throw ImportError(fmt::format("{}: {}", file.string(), error_text(in.get())));
  Writer out(archive_write_disk_new(), archive_write_free);
  // members are written under `into` (an absolute path, so libarchive's NOABSOLUTEPATHS cannot be
  // used): an absolute or ".." member name is refused here instead
  archive_write_disk_set_options(out.get(), ARCHIVE_EXTRACT_SECURE_NODOTDOT | ARCHIVE_EXTRACT_SECURE_SYMLINKS);
  archive_entry* entry = nullptr;
  std::uint64_t unpacked = 0;
  std::size_t members = 0;
  for (;;) {
    const int r = archive_read_next_header(in.get(), &entry);
    if (r == ARCHIVE_EOF) break;
    if (r < ARCHIVE_WARN) throw ImportError(fmt::format("{}: {}", file.string(), error_text(in.get())));
    // a header libarchive read with a warning may have no name (a malformed pax record), or one the
    // locale cannot spell: its UTF-8 form then, else the member is refused (fuzz_archive's finding:
    // a null name made std::string throw std::logic_error out of ArchiveInput)
    const char* name = archive_entry_pathname(entry);
    if (name == nullptr) name = archive_entry_pathname_utf8(entry);
    if (name == nullptr)
      throw ImportError(fmt::format("{}: member {} has no name ({})", file.string(), members + 1,
                                    r == ARCHIVE_WARN ? error_text(in.get()) : std::string("no path in its header")));
    const std::string member = name;
    if (fs::path(member).lexically_normal() == ".") {  // the directory unpacked into itself ("./" of `tar c .`)
      if (archive_entry_filetype(entry) == AE_IFDIR) continue;
      throw ImportError(
          fmt::format("{}: member '{}' names the archive's top directory, but is no directory", file.string(), printable(member)));
    }
    if (!safe_member(member))
      throw ImportError(fmt::format("{}: member '{}' would be written outside the directory", file.string(), printable(member)));
    if (const std::string kind = member_kind_problem(entry); !kind.empty())
      throw ImportError(
          fmt::format("{}: member '{}' {}: an archive's members must be regular files", file.string(), printable(member), kind));
    if (++members > limits.max_members)
      throw ImportError(fmt::format("{}: more than {} members (docs/hostile-inputs.md)", file.string(), limits.max_members));
    // the size the member declares is what it takes on disk (the writer extends a file to it: a
    // sparse member's holes), before a byte is written
    const la_int64_t declared = archive_entry_size_is_set(entry) ? archive_entry_size(entry) : 0;
    if (declared < 0 || static_cast<std::uint64_t>(declared) > limits.max_bytes - unpacked) too_large(file, member, limits.max_bytes);
    archive_entry_set_pathname(entry, (into / member).c_str());
    // the archive's permissions are not kept: the user reads every file and can remove the directory
    // (a read-only directory member would leave the temporary directory behind)
    archive_entry_set_perm(entry, archive_entry_filetype(entry) == AE_IFDIR ? 0755 : 0644);
    if (archive_write_header(out.get(), entry) < ARCHIVE_OK)
      throw ImportError(fmt::format("{}: {}: {}", file.string(), printable(member), error_text(out.get())));
    // (a member whose header gives no size is copied too, within the limit)
    if (declared > 0 || !archive_entry_size_is_set(entry)) copy_data(in.get(), out.get(), file, member, unpacked, limits.max_bytes);
    if (archive_write_finish_entry(out.get()) < ARCHIVE_OK)
      throw ImportError(fmt::format("{}: {}: {}", file.string(), printable(member), error_text(out.get())));
    std::error_code ec;  // what the member takes: its declared size, or as far as its data went
    const auto on_disk = fs::file_size(into / member, ec);
    unpacked += std::max<std::uint64_t>(static_cast<std::uint64_t>(declared), ec ? 0 : on_disk);
    if (unpacked > limits.max_bytes) too_large(file, member, limits.max_bytes);
  }
}

}  // namespace

ArchiveInput::ArchiveInput(const fs::path& input, const ArchiveLimits& limits) : input_(input) {
  std::error_code ec;
  if (fs::is_directory(input, ec)) {
    dir_ = input;
    return;
  }
  if (!fs::exists(input, ec)) throw ImportError(fmt::format("{}: no such file or directory", input.string()));
  temp_ = make_temp_dir();
  try {
    unpack(input, temp_, limits);
  } catch (...) {
    fs::remove_all(temp_, ec);
    throw;
  }
  dir_ = temp_;
}

std::string ArchiveInput::readable(std::string text) const {
  if (temp_.empty()) return text;
  const auto replace_every = [&text](const std::string& from, const std::string& to) {
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) text.replace(at, from.size(), to);
  };
  replace_every(temp_.string() + "/", input_.string() + ":");  // a file in the archive: archive:member
  replace_every(temp_.string(), input_.string());              // the unpacked directory itself: the archive
  return text;
}

ArchiveInput::~ArchiveInput() {
  std::error_code ec;
  if (!temp_.empty()) fs::remove_all(temp_, ec);
}

}  // namespace tern::core
