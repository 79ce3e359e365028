// core/apps/dds/include/dds_keystore.hpp: an SROS2-style DDS Security keystore, made with Debian's
// `openssl` command (`tern dds keystore create DIR`, `tern dds keystore add-node DIR NAME`).
//
//   DIR/public/ca.cert.pem            self-signed CA (EC prime256v1, 10 years); identity_ca.cert.pem and
//                                     permissions_ca.cert.pem are copies (one CA for both roles, as SROS2)
//   DIR/private/ca.key.pem            its key (identity_ca.key.pem, permissions_ca.key.pem: copies)
//   DIR/enclaves/governance.xml/.p7s  governance (OMG DDS Security 1.1, 9.4.1.2), S/MIME-signed by the CA:
//                                     no unauthenticated participants, join access control, RTPS,
//                                     discovery and liveliness ENCRYPT, every topic's data ENCRYPT
//   DIR/enclaves/<NAME>/              key.pem, cert.pem (CN=<NAME>, signed by the CA), identity_ca.cert.pem,
//                                     permissions_ca.cert.pem, governance.p7s, permissions.xml/.p7s
//                                     (publish and subscribe on every topic of domains 0..232)
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace tern::core {

/// The enclave the vehicle uses unless dds.security.enclave names another.
inline constexpr std::string_view kVehicleEnclave = "vehicle";
/// The enclave of the command line's client unless --enclave (or TERN_DDS_ENCLAVE) names another.
inline constexpr std::string_view kGroundEnclave = "ground";

/// Letters, digits and '_', in parts separated by single '/' (ROS 2 enclave names without the
/// leading '/'); not empty.
bool is_enclave_name(const std::string& name);

/// Makes the CA and the signed governance in `dir` (created; must not hold a keystore yet).
/// Throws DdsError with one line (openssl's own error when it fails, "openssl not found" without it).
void create_keystore(const std::filesystem::path& dir);

/// Makes enclave `name` in the keystore `dir`: a key, a certificate signed by the CA, the CA
/// certificates, the governance and the signed permissions. Throws DdsError (no keystore in
/// `dir`, a bad name, an enclave that exists, openssl's error).
void add_keystore_node(const std::filesystem::path& dir, const std::string& name);

}  // namespace tern::core
