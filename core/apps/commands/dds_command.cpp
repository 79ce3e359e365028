// core/apps/commands/dds_command.cpp: `tern dds keystore ...` and the clients' DDS Security options.
#include "commands/dds_command.hpp"

#include <cstdlib>
#include <memory>

#include <fmt/format.h>

#include "commands/commands.hpp"
#include "dds_keystore.hpp"

namespace tern::core {

namespace {

struct DdsCommand {
  CLI::App* app = nullptr;
  CLI::App* create = nullptr;
  CLI::App* add_node = nullptr;
  std::string dir, name;
};

void add_keystore_options(CLI::App& app, DdsCommand& c) {
  c.app = app.add_subcommand("dds", "DDS Security: make a keystore for `dds.security` and the clients' --keystore");
  c.app->require_subcommand(1);
  auto* ks = c.app->add_subcommand("keystore", "an SROS2-style keystore made with openssl: CA, governance, enclaves");
  ks->require_subcommand(1);
  c.create = ks->add_subcommand("create", "make DIR's CA (EC prime256v1, self-signed) and its signed governance");
  c.create->add_option("dir", c.dir, "keystore directory")->required();
  c.add_node = ks->add_subcommand("add-node", "make enclave NAME: key, CA-signed certificate, signed permissions");
  c.add_node->add_option("dir", c.dir, "keystore directory (made by `tern dds keystore create`)")->required();
  c.add_node->add_option("name", c.name, "enclave name: 'vehicle' (the vehicle's default), 'ground' (the clients' default), ...")
      ->required();
}

/// Runs the parsed subcommand: 0. Throws DdsError or std::filesystem::filesystem_error with one
/// line (main prints it as "tern: error: ..." and exits 1).
int run_keystore_command(const DdsCommand& c) {
  if (c.create->parsed()) {
    create_keystore(c.dir);
    fmt::print(
        "keystore created: {} (CA public/ca.cert.pem, governance enclaves/governance.p7s)\n"
        "next: tern dds keystore add-node {} {}; tern dds keystore add-node {} {}\n",
        c.dir, c.dir, kVehicleEnclave, c.dir, kGroundEnclave);
  } else {
    add_keystore_node(c.dir, c.name);
    fmt::print("enclave '{}' added: {}/enclaves/{} (cert.pem CN={}, permissions.p7s)\n", c.name, c.dir, c.name, c.name);
  }
  return 0;
}

}  // namespace

Command add_dds_command(CLI::App& app) {
  auto c = std::make_shared<DdsCommand>();
  add_keystore_options(app, *c);
  return {c->app, [c] { return run_keystore_command(*c); }};
}

void apply_client_security(DdsOptions& o, const std::optional<std::string>& keystore, const std::optional<std::string>& enclave) {
  const char* env_keystore = std::getenv("TERN_DDS_KEYSTORE");
  const char* env_enclave = std::getenv("TERN_DDS_ENCLAVE");
  if (keystore)
    o.security = DdsSecurity{*keystore, ""};
  else if (env_keystore != nullptr && *env_keystore != '\0')
    o.security = DdsSecurity{env_keystore, ""};
  if (!o.security) return;
  if (enclave)
    o.security->enclave = *enclave;
  else if (env_enclave != nullptr && *env_enclave != '\0')
    o.security->enclave = env_enclave;
  else
    o.security->enclave = std::string(kGroundEnclave);
  if (!is_enclave_name(o.security->enclave))
    throw DdsError("'" + o.security->enclave + "' is not an enclave name (letters, digits, '_', '/')");
}

}  // namespace tern::core
