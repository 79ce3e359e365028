// core/src/commands/dds_command.hpp: `tern dds keystore create DIR` and `tern dds keystore add-node DIR
// NAME` (core/dds/include/dds_keystore.hpp does the work), and the DDS Security of the command
// line's clients (--keystore, --enclave; TERN_DDS_KEYSTORE, TERN_DDS_ENCLAVE).
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "dds_bridge.hpp"

namespace tern::core {

struct DdsCommand {
  CLI::App* app = nullptr;
  CLI::App* create = nullptr;
  CLI::App* add_node = nullptr;
  std::string dir, name;
};

/// Adds `dds keystore create|add-node` to the command line.
void add_dds_command(CLI::App& app, DdsCommand& c);
/// Runs the parsed subcommand: 0. Throws DdsError or std::filesystem::filesystem_error with one
/// line (main prints it as "tern: error: ..." and exits 1).
int run_dds_command(const DdsCommand& c);

/// A client's security: the keystore from `keystore` (--keystore), else $TERN_DDS_KEYSTORE, else
/// the config's dds.security.keystore (already in `o`); the enclave from `enclave` (--enclave),
/// else $TERN_DDS_ENCLAVE, else "ground". No keystore anywhere: security stays off.
void apply_client_security(DdsOptions& o, const std::optional<std::string>& keystore, const std::optional<std::string>& enclave);

}  // namespace tern::core
