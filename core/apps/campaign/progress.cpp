#include "progress.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>

#include <fmt/format.h>

namespace tern::campaign {

namespace {

std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string clock_text(double s) {
  const long t = static_cast<long>(s + 0.5);
  return t >= 3600 ? fmt::format("{}h{:02}m", t / 3600, t / 60 % 60) : fmt::format("{}m{:02}s", t / 60, t % 60);
}

}  // namespace

Progress::Progress(std::size_t total, std::size_t already)
    : total_(total), already_(already), start_ns_(now_ns()), tty_(isatty(STDERR_FILENO) != 0) {
  if (already_ > 0) std::fprintf(stderr, "campaign: %zu flights already flown (resumed), %zu to fly\n", already_, total_);
  if (tty_) draw();
}

void Progress::done(bool failed) {
  ++done_;
  if (failed) ++failed_;
  const std::size_t decile = total_ ? done_ * 10 / total_ : 10;
  if (tty_ || decile != last_decile_) draw();
  last_decile_ = decile;
}

void Progress::draw() {
  const double elapsed = static_cast<double>(now_ns() - start_ns_) * 1e-9;
  const std::string eta = done_ ? clock_text(elapsed / static_cast<double>(done_) * static_cast<double>(total_ - done_)) : "-";
  const std::size_t width = 30, filled = total_ ? width * done_ / total_ : width;
  const std::string line = fmt::format("[{}{}] {}/{} flights, {} failed, {} elapsed, ETA {}", std::string(filled, '#'),
                                       std::string(width - filled, '.'), done_, total_, failed_, clock_text(elapsed), eta);
  if (tty_) {
    std::fprintf(stderr, "\r%s\033[K", line.c_str());
  } else {
    std::fprintf(stderr, "campaign: %s\n", line.c_str());
  }
  std::fflush(stderr);
}

void Progress::finish() {
  if (tty_) std::fputs("\n", stderr);
}

}  // namespace tern::campaign
