#include "files/log_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <fmt/format.h>

namespace tern::core {

std::string cannot_write(const fs::path& p, int err) { return fmt::format("cannot write '{}': {}", p.string(), std::strerror(err)); }

std::size_t write_all(int fd, std::string_view text, int& err) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      err = n == 0 ? ENOSPC : errno;  // write() returning 0 for a non-empty buffer: no room
      break;
    }
  }
  return done;
}

namespace {

int open_for_writing(const fs::path& p) { return ::open(p.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644); }

}  // namespace

void LogHealth::fail(std::string what) {
  std::lock_guard lk(mu_);
  if (failed_.load(std::memory_order_relaxed)) return;
  error_ = std::move(what);
  failed_.store(true, std::memory_order_release);
}

std::string LogHealth::error() const {
  std::lock_guard lk(mu_);
  return error_;
}

std::optional<std::string> LogHealth::take_unreported() {
  std::lock_guard lk(mu_);
  if (!failed_.load(std::memory_order_relaxed) || reported_) return std::nullopt;
  reported_ = true;
  return error_;
}

LogFile::LogFile(fs::path path, LogHealth& health) : path_(std::move(path)), health_(health) {
  if (health_.failed()) return;
  fd_ = open_for_writing(path_);
  if (fd_ < 0) health_.fail(cannot_write(path_, errno));
}

LogFile::~LogFile() {
  if (fd_ >= 0) ::close(fd_);
}

void LogFile::append(std::string_view text) {
  if (fd_ < 0 || health_.failed()) return;
  int err = 0;
  const std::size_t n = write_all(fd_, text, err);
  if (err != 0) {
    fail(err, text.substr(0, n));
    return;
  }
  size_ += static_cast<off_t>(n);
}

void LogFile::fail(int err, std::string_view written) {
  health_.fail(cannot_write(path_, err));
  // keep whole lines only: the part of `text` that made it, up to its last line end
  const auto last_eol = written.rfind('\n');
  const off_t keep = size_ + (last_eol == std::string_view::npos ? 0 : static_cast<off_t>(last_eol + 1));
  if (::ftruncate(fd_, keep) != 0) {
    // nothing more to do: a reader drops a partial last line
  }
  ::close(fd_);
  fd_ = -1;
}

bool write_file_atomically(const fs::path& path, std::string_view text, LogHealth& health) {
  const fs::path tmp = path.string() + ".tmp";
  const int fd = open_for_writing(tmp);
  if (fd < 0) {
    health.fail(cannot_write(path, errno));
    return false;
  }
  int err = 0;
  write_all(fd, text, err);
  if (::close(fd) != 0 && err == 0) err = errno;
  if (err == 0 && std::rename(tmp.c_str(), path.c_str()) != 0) err = errno;
  if (err != 0) {
    health.fail(cannot_write(path, err));
    ::unlink(tmp.c_str());
    return false;
  }
  return true;
}

}  // namespace tern::core
