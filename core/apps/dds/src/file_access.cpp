// core/apps/dds/src/file_access.cpp: see file_access.hpp.
#include "file_access.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <unistd.h>

#include "dds_bridge.hpp"

namespace tern::core::ddsi {

namespace fs = std::filesystem;

namespace {

/// The name as sent, quoted, printable (a control character shows as '?').
std::string quoted(const std::string& name) {
  std::string s = name.substr(0, 200);
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return "'" + s + (name.size() > 200 ? "...'" : "'");
}

bool inside(const fs::path& p, const fs::path& dir) {
  const auto [d, pp] = std::mismatch(dir.begin(), dir.end(), p.begin(), p.end());
  return d == dir.end();
}

std::string list(const std::vector<fs::path>& dirs) {
  std::string s;
  for (const auto& d : dirs) s += (s.empty() ? "" : ", ") + d.string();
  return s.empty() ? "none" : s;
}

}  // namespace

FileAccess::FileAccess(std::vector<fs::path> dirs) {
  for (auto& d : dirs) {
    std::error_code ec;
    fs::path c = fs::weakly_canonical(d, ec);
    dirs_.push_back(ec ? d.lexically_normal() : c);
  }
}

fs::path FileAccess::resolve(const std::string& request, const std::string& name) const {
  auto refuse = [&](const std::string& why) { return DdsError(request + ": refused " + quoted(name) + ": " + why); };
  if (name.empty()) throw DdsError(request + ": refused: no file name");
  if (std::any_of(name.begin(), name.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
    throw refuse("control characters are not allowed in a file name");
  const fs::path p(name);
  for (const auto& part : p)
    if (part == "..") throw refuse("'..' is not allowed (name a file inside " + list(dirs_) + ")");
  const std::string ext = p.extension().string();
  if (ext != ".yaml" && ext != ".yml") throw refuse("only .yaml or .yml files");
  if (dirs_.empty()) throw refuse("this vehicle allows no directory for it");
  const fs::path full = p.is_absolute() ? p.lexically_normal() : (dirs_.front() / p).lexically_normal();
  std::error_code ec;
  const fs::path real = fs::weakly_canonical(full, ec);  // follows symbolic links
  if (ec) throw refuse("cannot resolve the path");
  for (const auto& d : dirs_)
    if (inside(real, d)) return real;
  throw refuse("outside the allowed directories (" + list(dirs_) + ")");
}

fs::path FileAccess::for_reading(const std::string& request, const std::string& name) const {
  const fs::path p = resolve(request, name);
  if (!fs::is_regular_file(p)) throw DdsError(request + ": no such file on the vehicle: " + p.string());
  return p;
}

fs::path FileAccess::for_writing(const std::string& request, const std::string& name, bool overwrite) const {
  const fs::path p = resolve(request, name);
  std::error_code ec;
  if (fs::exists(fs::symlink_status(p, ec)) && !overwrite)
    throw DdsError(request + ": refused: " + p.string() + " exists (ask to overwrite it: --overwrite)");
  if (fs::exists(p) && !fs::is_regular_file(p)) throw DdsError(request + ": refused: " + p.string() + " is not a regular file");
  if (!fs::is_directory(p.parent_path())) throw DdsError(request + ": no such directory on the vehicle: " + p.parent_path().string());
  return p;
}

void FileAccess::write_file(const std::string& request, const fs::path& path, const std::string& text, bool overwrite) {
  const int flags = O_WRONLY | O_CREAT | O_NOFOLLOW | O_CLOEXEC | (overwrite ? O_TRUNC : O_EXCL);
  const int fd = ::open(path.c_str(), flags, 0644);
  if (fd < 0) {
    const int e = errno;
    if (e == EEXIST) throw DdsError(request + ": refused: " + path.string() + " exists (ask to overwrite it: --overwrite)");
    if (e == ELOOP) throw DdsError(request + ": refused: " + path.string() + " is a symbolic link");
    throw DdsError(request + ": cannot write " + path.string() + ": " + std::strerror(e));
  }
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int e = errno;
      ::close(fd);
      throw DdsError(request + ": cannot write " + path.string() + ": " + std::strerror(e));
    }
    done += static_cast<size_t>(n);
  }
  if (::close(fd) != 0) throw DdsError(request + ": cannot write " + path.string() + ": " + std::strerror(errno));
}

}  // namespace tern::core::ddsi
