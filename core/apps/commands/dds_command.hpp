// core/apps/commands/dds_command.hpp: the DDS Security of the command line's clients (--keystore,
// --enclave; TERN_DDS_KEYSTORE, TERN_DDS_ENCLAVE). dds_command.cpp also holds `tern dds keystore
// create DIR` and `tern dds keystore add-node DIR NAME` (commands.hpp; core/apps/dds/include/
// dds_keystore.hpp does the work).
#pragma once

#include <optional>
#include <string>

#include "dds_bridge.hpp"

namespace tern::core {

/// A client's security: the keystore from `keystore` (--keystore), else $TERN_DDS_KEYSTORE, else
/// the config's dds.security.keystore (already in `o`); the enclave from `enclave` (--enclave),
/// else $TERN_DDS_ENCLAVE, else "ground". No keystore anywhere: security stays off.
void apply_client_security(DdsOptions& o, const std::optional<std::string>& keystore, const std::optional<std::string>& enclave);

}  // namespace tern::core
