// core/apps/dds/src/keystore_check.hpp: the files of one enclave of a keystore (dds_keystore.hpp's
// layout, SROS2's) and their check before Fast DDS reads them, so that a missing or bad file is
// one error line naming it (Fast DDS itself only logs "cannot create participant").
#pragma once

#include <filesystem>

#include "dds_bridge.hpp"

namespace tern::core::ddsi {

struct EnclaveFiles {
  std::filesystem::path identity_ca, certificate, private_key;    // DDS:Auth:PKI-DH
  std::filesystem::path permissions_ca, governance, permissions;  // DDS:Access:Permissions
};

/// <keystore>/enclaves/<enclave>/{identity_ca.cert.pem, cert.pem, key.pem, permissions_ca.cert.pem,
/// governance.p7s, permissions.p7s}.
EnclaveFiles enclave_files(const DdsSecurity& s);

/// Throws DdsError "dds.security: <file>: <what is wrong>" (missing, unreadable, not PEM, expired,
/// key not the certificate's, certificate not signed by the identity CA, governance or permissions
/// not signed by the permissions CA) for the first bad file.
void check_enclave(const DdsSecurity& s, const EnclaveFiles& f);

}  // namespace tern::core::ddsi
