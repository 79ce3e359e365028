// tests/hostile/marker_library.cpp: a shared library that is no tern plugin, whose constructor
// writes the file TERN_HOSTILE_MARKER names as soon as the library is loaded. test_hostile.sh puts
// it in a flight log as libtern_estimator_ekf.so: `tern replay LOG` must never load it (a log never
// runs code), while a plugin path the user sets (TERN_PLUGIN_PATH) does load it, which proves the
// marker would show a load.
#include <cstdio>
#include <cstdlib>

namespace {

__attribute__((constructor)) void mark_loaded() {
  const char* path = std::getenv("TERN_HOSTILE_MARKER");
  if (path == nullptr) return;
  if (std::FILE* f = std::fopen(path, "w")) {
    std::fputs("loaded\n", f);
    std::fclose(f);
  }
}

}  // namespace
