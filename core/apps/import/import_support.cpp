#include "import/import_support.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace tern::core {

namespace fs = std::filesystem;

namespace {
bool ends_with(const std::string& name, const std::string& suffix) {
  return name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool holds(const fs::path& dir, const std::vector<std::string>& suffixes) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    for (const auto& s : suffixes)
      if (e.is_regular_file() && ends_with(e.path().filename().string(), s)) return true;
  return false;
}
}  // namespace

fs::path directory_holding(const fs::path& in, const std::vector<std::string>& suffixes) {
  std::error_code ec;
  if (!fs::is_directory(in, ec)) throw ImportError(fmt::format("{}: not a directory or a .zip/.tar.gz archive", in.string()));
  if (holds(in, suffixes)) return in;
  fs::path found;
  for (const auto& e : fs::directory_iterator(in, ec)) {
    if (!e.is_directory() || !holds(e.path(), suffixes)) continue;
    if (!found.empty()) throw ImportError(fmt::format("{}: several subdirectories hold *{}: name one", in.string(), suffixes.front()));
    found = e.path();
  }
  if (found.empty()) throw ImportError(fmt::format("{}: no *{} in it (nor in a subdirectory)", in.string(), suffixes.front()));
  return found;
}

fs::path file_ending_with(const fs::path& dir, const std::string& suffix) {
  fs::path found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (!e.is_regular_file() || name.size() < suffix.size() || name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    if (!found.empty())
      throw ImportError(fmt::format("{}: several files end with '{}' ({}, {})", dir.string(), suffix, found.filename().string(), name));
    found = e.path();
  }
  return found;
}

void StampOrder::report(const fs::path& file, ImportReport& report) const {
  if (dropped_ > 0) report.warnings.push_back(fmt::format("{}: {} rows dropped: their time goes backwards", file.string(), dropped_));
}

void IntervalStats::add(Nanos stamp) {
  if (n_ == 0) {
    first_ = stamp;
  } else {
    const Nanos d = stamp - last_;
    min_ = n_ == 1 ? d : std::min(min_, d);
    max_ = n_ == 1 ? d : std::max(max_, d);
  }
  last_ = stamp;
  ++n_;
}

void AirborneWindow::write_to(SensorLogMeta& meta) const {
  if (!first_) return;
  meta.airborne = {to_seconds(*first_), to_seconds(*last_)};
  meta.notes.push_back(fmt::format("airborne: the first to the last GNSS fix at >= {:.0f} m/s horizontal speed ({:.3f} s to {:.3f} s)",
                                   kSpeed, to_seconds(*first_), to_seconds(*last_)));
}

std::string IntervalStats::describe() const {
  if (n_ < 2) return fmt::format("{} samples", n_);
  return fmt::format("{} samples, {:.1f} Hz mean, intervals {:.1f} to {:.1f} ms", n_, 1.0 / mean_s(), static_cast<double>(min_) * 1e-6,
                     static_cast<double>(max_) * 1e-6);
}

}  // namespace tern::core
