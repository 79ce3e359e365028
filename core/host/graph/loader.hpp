// core/host/graph/loader.hpp: finds plugin shared objects, checks their handshake, creates instances.
//
// A library is opened with RTLD_LOCAL | RTLD_NOW (Boost.DLL). Before any C++ code of the plugin
// runs, the host reads its C handshake (tern_plugin_handshake_v1) and checks the magic number,
// the SDK API version, the ABI tag and the layout fingerprint of every standard message type.
// Instances hold a reference to their library; the library is unloaded after the last instance
// is destroyed (Loader::unload then verifies it is really gone).
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "tern/plugin.hpp"

namespace boost::dll {
class shared_library;
}

namespace tern::core {

namespace fs = std::filesystem;

/// The handshake of a plugin, copied out of the library (valid after unload).
struct PluginInfo {
  std::string name;
  PluginKind kind = PluginKind::generic;
  std::string description;
  fs::path path;
  std::string sha256;  ///< of the library's bytes when it was opened (hex; `tern swap` compares them)
};

/// SHA-256 of a file's bytes, 64 lowercase hex digits (OpenSSL). Throws ConfigError when the file
/// cannot be read.
std::string file_sha256(const fs::path& path);

/// An open plugin library. Destroy every Plugin it created before destroying it.
class PluginLibrary {
 public:
  PluginLibrary(std::unique_ptr<boost::dll::shared_library> lib, PluginInfo info);
  ~PluginLibrary();
  const PluginInfo& info() const { return info_; }
  /// A new instance (throws ConfigError if the factory fails).
  std::unique_ptr<Plugin> create() const;

 private:
  std::unique_ptr<boost::dll::shared_library> lib_;
  PluginInfo info_;
  Plugin* (*factory_)() = nullptr;
};

/// Directories searched for libtern_<name>.so, in order: the config's plugin_path, the
/// directories in TERN_PLUGIN_PATH, the build tree's plugin directory, the install prefix's.
std::vector<fs::path> plugin_search_path(const std::vector<fs::path>& config_dirs);

/// Finds a plugin by name (or a path to a .so). Throws ConfigError naming the search path.
fs::path find_plugin(const std::string& name_or_path, const std::vector<fs::path>& search_path);

/// Checks the file (check_elf: complete, 64-bit, this machine, a shared object), opens it and
/// checks its handshake. Throws ConfigError on any problem, naming the file or the plugin and
/// what is wrong; the library is closed again before the throw.
std::shared_ptr<PluginLibrary> open_plugin(const fs::path& path);

/// Every libtern_*.so in the search path (first found wins for each name).
std::vector<fs::path> discover_plugins(const std::vector<fs::path>& search_path);

/// True when the shared object at `path` is currently mapped in this process
/// (dlopen(path, RTLD_NOLOAD) succeeds).
bool is_loaded(const fs::path& path);

}  // namespace tern::core
