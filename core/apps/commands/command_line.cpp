// core/apps/commands/command_line.cpp: what every command of `tern` shares (command_line.hpp).
#include "commands/command_line.hpp"

#include <algorithm>
#include <cstdio>

#include "tern/input_file.hpp"

#ifndef TERN_SOURCE_DIR
#define TERN_SOURCE_DIR ""
#endif
#ifndef TERN_INSTALL_DATA_DIR
#define TERN_INSTALL_DATA_DIR ""
#endif

namespace fs = std::filesystem;

namespace tern::core {

fs::path exe_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

fs::path default_config() {
  // an installed tern: <prefix>/share/tern; a build tree's tern: the source tree
  for (const fs::path& base : {exe_dir() / ".." / "share" / "tern", fs::path(TERN_SOURCE_DIR), fs::path(TERN_INSTALL_DATA_DIR)}) {
    if (base.empty()) continue;
    const fs::path p = (base / "configs" / "missions" / "default.yaml").lexically_normal();
    if (fs::exists(p)) return p;
  }
  return fs::path("configs/missions/default.yaml");
}

std::string terminal_line(const std::string& msg) {
  const std::string escaped = printable(msg, std::string::npos);
  std::string out;
  std::size_t word = 0;  // characters since the last space
  for (std::size_t i = 0; i < escaped.size(); ++i) {
    word = escaped[i] == ' ' ? 0 : word + 1;
    if (word <= kMaxEchoChars) {
      out += escaped[i];
    } else if (word == kMaxEchoChars + 1) {
      out += "...";
    }
  }
  return out;
}

std::string terminal_text(const std::string& text) {
  std::string out;
  for (std::size_t start = 0; start <= text.size();) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    out += printable(std::string_view(text).substr(start, end - start), std::string::npos);
    if (end < text.size()) out += '\n';
    start = end + 1;
  }
  return out;
}

int fail(const std::string& msg) {
  std::fprintf(stderr, "tern: error: %s\n", terminal_line(msg).c_str());
  return 1;
}

bool report_missions(const MissionReport& r, bool notes) {
  if (notes)
    for (const auto& n : r.notes) std::fprintf(stderr, "tern: note: %s\n", terminal_line(n).c_str());
  for (const auto& w : r.warnings) std::fprintf(stderr, "tern: warning: %s\n", terminal_line(w).c_str());
  for (const auto& e : r.errors) std::fprintf(stderr, "tern: error: %s\n", terminal_line(e).c_str());
  return r.errors.empty();
}

}  // namespace tern::core
