#include "graph/loader.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <map>
#include <set>

#include <fstream>

#include <boost/dll/shared_library.hpp>
#include <fmt/format.h>
#include <openssl/evp.h>

#include "graph/elf_check.hpp"
#include "config/error.hpp"

#ifndef TERN_BUILD_PLUGIN_DIR
#define TERN_BUILD_PLUGIN_DIR ""
#endif
#ifndef TERN_INSTALL_PLUGIN_DIR
#define TERN_INSTALL_PLUGIN_DIR ""
#endif

namespace tern::core {

namespace {

// The host's own view of the standard messages, to compare with each plugin's.
#define TERN_HOST_FP_(T) {std::string(T::type_name), ::tern::reflect::fingerprint<T>()},
const std::map<std::string, std::uint64_t>& host_fingerprints() {
  static const std::map<std::string, std::uint64_t> fps = {TERN_STANDARD_MESSAGES(TERN_HOST_FP_)};
  return fps;
}
#undef TERN_HOST_FP_

fs::path self_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

}  // namespace

PluginLibrary::PluginLibrary(std::unique_ptr<boost::dll::shared_library> lib, PluginInfo info)
    : lib_(std::move(lib)), info_(std::move(info)) {
  factory_ = lib_->get_alias<Plugin*()>(TERN_STR(TERN_FACTORY_ALIAS));
}

PluginLibrary::~PluginLibrary() {
  if (lib_) lib_->unload();
}

std::unique_ptr<Plugin> PluginLibrary::create() const {
  try {
    std::unique_ptr<Plugin> p(factory_());
    if (!p) throw ConfigError("factory returned null");
    return p;
  } catch (const std::exception& e) {
    throw ConfigError(fmt::format("plugin '{}' ({}): cannot create an instance: {}", info_.name, info_.path.string(), e.what()));
  }
}

std::vector<fs::path> plugin_search_path(const std::vector<fs::path>& config_dirs) {
  std::vector<fs::path> out = config_dirs;
  if (const char* env = std::getenv("TERN_PLUGIN_PATH")) {
    std::string s(env);
    std::size_t start = 0;
    while (start <= s.size()) {
      const std::size_t colon = s.find(':', start);
      const std::string part = s.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
      if (!part.empty()) out.emplace_back(fs::absolute(part).lexically_normal());
      if (colon == std::string::npos) break;
      start = colon + 1;
    }
  }
  // The plugins that came with this tern binary: next to it in an install prefix
  // (<prefix>/bin/tern -> <prefix>/lib/tern/plugins), or the build tree's when the binary is
  // the build tree's.
  const fs::path exe_dir = self_dir();
  const std::string build_dir = TERN_BUILD_PLUGIN_DIR;
  std::error_code ec;
  const bool in_build_tree =
      !build_dir.empty() && !exe_dir.empty() && fs::equivalent(fs::path(build_dir).parent_path(), exe_dir.parent_path(), ec);
  if (in_build_tree && fs::is_directory(build_dir)) out.emplace_back(build_dir);
  if (!exe_dir.empty()) {
    const fs::path rel = (exe_dir / ".." / "lib" / "tern" / "plugins").lexically_normal();
    if (fs::is_directory(rel)) out.push_back(rel);
  }
  const std::string install_dir = TERN_INSTALL_PLUGIN_DIR;
  if (!install_dir.empty() && fs::is_directory(install_dir)) out.emplace_back(install_dir);
  // de-duplicate, keep order
  std::vector<fs::path> uniq;
  std::set<std::string> seen;
  for (auto& p : out)
    if (seen.insert(p.lexically_normal().string()).second) uniq.push_back(p.lexically_normal());
  return uniq;
}

fs::path find_plugin(const std::string& name, const std::vector<fs::path>& search_path) {
  if (name.find('/') != std::string::npos || (name.size() > 3 && name.substr(name.size() - 3) == ".so")) {
    const fs::path p = fs::absolute(name).lexically_normal();
    if (!fs::exists(p)) throw ConfigError(fmt::format("plugin file '{}' not found", p.string()));
    return p;
  }
  const std::string file = "libtern_" + name + ".so";
  for (const auto& dir : search_path) {
    const fs::path p = dir / file;
    if (fs::exists(p)) return p;
  }
  std::vector<std::string> dirs, known;
  for (const auto& d : search_path) dirs.push_back(d.string());
  for (const auto& p : discover_plugins(search_path)) {
    std::string stem = p.filename().string();
    known.push_back(stem.substr(8, stem.size() - 11));
  }
  throw ConfigError(fmt::format("plugin '{}' not found: no {} in the plugin search path [{}]{}", name, file, fmt::join(dirs, ", "),
                                did_you_mean(name, known)));
}

std::vector<fs::path> discover_plugins(const std::vector<fs::path>& search_path) {
  std::vector<fs::path> out;
  std::set<std::string> names;
  for (const auto& dir : search_path) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    std::vector<fs::path> here;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
      const std::string fn = e.path().filename().string();
      if (fn.rfind("libtern_", 0) == 0 && fn.size() > 11 && fn.substr(fn.size() - 3) == ".so") here.push_back(e.path());
    }
    std::sort(here.begin(), here.end());
    for (auto& p : here)
      if (names.insert(p.filename().string()).second) out.push_back(p);
  }
  return out;
}

std::string file_sha256(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError("cannot read '" + path.string() + "' to hash it");
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx(EVP_MD_CTX_new(), EVP_MD_CTX_free);
  if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1) throw ConfigError("sha256: OpenSSL cannot start a digest");
  char buf[1 << 16];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    EVP_DigestUpdate(ctx.get(), buf, static_cast<std::size_t>(in.gcount()));
    if (in.eof()) break;
  }
  if (in.bad()) throw ConfigError("cannot read '" + path.string() + "' to hash it");
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int n = 0;
  EVP_DigestFinal_ex(ctx.get(), md, &n);
  std::string hex;
  for (unsigned int i = 0; i < n; ++i) hex += fmt::format("{:02x}", md[i]);
  return hex;
}

std::shared_ptr<PluginLibrary> open_plugin(const fs::path& path) {
  check_elf(path);                         // a truncated file would raise SIGBUS inside dlopen
  std::string sha256 = file_sha256(path);  // the bytes about to be loaded
  auto lib = std::make_unique<boost::dll::shared_library>();
  boost::dll::fs::error_code ec;
  lib->load(path.string(), ec, boost::dll::load_mode::rtld_local | boost::dll::load_mode::rtld_now);
  if (ec || !lib->is_loaded()) {
    const char* dl = dlerror();
    throw ConfigError(fmt::format("cannot load '{}': {}", path.string(), dl ? dl : ec.message()));
  }
  const char* sym = TERN_STR(TERN_HANDSHAKE_SYMBOL);
  if (!lib->has(sym)) {
    throw ConfigError(fmt::format("'{}' is not a tern plugin: it has no {} symbol (build it with tern_add_plugin() and TERN_PLUGIN())",
                                  path.string(), sym));
  }
  const auto& hs = lib->get<const tern_plugin_handshake>(sym);
  const std::string who =
      fmt::format("plugin '{}' ({})", hs.magic == TERN_HANDSHAKE_MAGIC && hs.plugin_name ? hs.plugin_name : "?", path.string());
  if (hs.magic != TERN_HANDSHAKE_MAGIC)
    throw ConfigError(fmt::format("'{}' is not a tern plugin: bad handshake magic {:#x}", path.string(), hs.magic));
  if (hs.sdk_api_version != kSdkApiVersion)
    throw ConfigError(
        fmt::format("{}: SDK API version mismatch: plugin built for API {}, this host speaks API {}; rebuild the plugin against this tern",
                    who, hs.sdk_api_version, kSdkApiVersion));
  if (hs.abi_tag == nullptr || std::string(hs.abi_tag) != TERN_ABI_TAG)
    throw ConfigError(
        fmt::format("{}: ABI mismatch: plugin built with '{}', host with '{}'; rebuild the plugin with the host's compiler settings", who,
                    hs.abi_tag ? hs.abi_tag : "", TERN_ABI_TAG));
  const auto& host_fps = host_fingerprints();
  for (std::uint32_t i = 0; i < hs.message_count; ++i) {
    const auto& m = hs.messages[i];
    const std::string tname = m.type_name ? m.type_name : "";
    auto it = host_fps.find(tname);
    if (it == host_fps.end()) continue;  // a message this host does not know: checked per port
    if (it->second != m.fingerprint)
      throw ConfigError(fmt::format(
          "{}: message fingerprint mismatch: {} is {:016x} in the plugin, {:016x} in the host; rebuild the plugin against this tern's SDK",
          who, tname, m.fingerprint, it->second));
  }
  const auto kind = plugin_kind_from_name(hs.kind ? hs.kind : "");
  if (!kind) throw ConfigError(fmt::format("{}: unknown plugin kind '{}'", who, hs.kind ? hs.kind : ""));
  if (!lib->has(TERN_STR(TERN_FACTORY_ALIAS)))
    throw ConfigError(fmt::format("{}: no factory symbol {}", who, TERN_STR(TERN_FACTORY_ALIAS)));
  PluginInfo info{hs.plugin_name, *kind, hs.description ? hs.description : "", path, std::move(sha256)};
  return std::make_shared<PluginLibrary>(std::move(lib), std::move(info));
}

bool is_loaded(const fs::path& path) {
  void* h = dlopen(path.c_str(), RTLD_NOLOAD | RTLD_NOW);
  if (h == nullptr) return false;
  dlclose(h);
  return true;
}

}  // namespace tern::core
