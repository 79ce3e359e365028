// core/apps/dds/src/file_access.hpp: which files a network request may read or write on the vehicle
// (issue 20, item 3). A service that takes a file name from the network (param_save,
// load_mission_from_file) resolves it here first:
//   - a relative name is taken inside the first allowed directory; an absolute one must lie in
//     one of them; a '..' component, an empty name, a control character and a name not ending in
//     .yaml/.yml are refused;
//   - symbolic links are followed before the check (weakly_canonical), so a link in an allowed
//     directory cannot lead outside it;
//   - writing refuses an existing file unless the request asks to overwrite it; write_file opens
//     with O_NOFOLLOW and, without overwrite, O_EXCL, so a link or file put there between the
//     check and the write is refused too (no check-then-use race).
// Every refusal is one line naming the request and the name as sent (never a file's contents).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace tern::core::ddsi {

class FileAccess {
 public:
  /// `dirs`: the allowed directories (absolute; the first one takes relative names). An empty
  /// list refuses every name.
  explicit FileAccess(std::vector<std::filesystem::path> dirs);

  /// The file to read for `request` (e.g. "load_mission_from_file"). Throws DdsError: refused
  /// name, outside the allowed directories, or no such file.
  std::filesystem::path for_reading(const std::string& request, const std::string& name) const;
  /// The file to write. Throws DdsError: refused name, outside, or it exists and !overwrite.
  std::filesystem::path for_writing(const std::string& request, const std::string& name, bool overwrite) const;

  /// Writes `text` to `path` (from for_writing): O_NOFOLLOW always (a symbolic link planted at
  /// `path` is refused), O_EXCL unless `overwrite`, mode 0644. Throws DdsError naming `request`
  /// and the path (exists, link, or the system's error, e.g. disk full).
  static void write_file(const std::string& request, const std::filesystem::path& path, const std::string& text, bool overwrite);

  const std::vector<std::filesystem::path>& dirs() const { return dirs_; }

 private:
  std::filesystem::path resolve(const std::string& request, const std::string& name) const;
  std::vector<std::filesystem::path> dirs_;  // weakly_canonical
};

}  // namespace tern::core::ddsi
