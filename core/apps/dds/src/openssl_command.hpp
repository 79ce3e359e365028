// core/apps/dds/src/openssl_command.hpp: runs Debian's `openssl` command (package openssl) for the
// keystore commands; its output goes nowhere, its last error line into the exception.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace tern::core::ddsi {

/// The `openssl` program found on PATH; empty when there is none.
std::filesystem::path find_openssl();

/// Throws DdsError "openssl not found: ..." when find_openssl() finds none.
void require_openssl();

/// Runs `openssl args...` in directory `cwd` (no shell). Throws DdsError "openssl ARGS[0]: <its
/// last error line>" when it fails, "openssl not found: install Debian's openssl package" without it.
void run_openssl(const std::vector<std::string>& args, const std::filesystem::path& cwd);

}  // namespace tern::core::ddsi
