// core/apps/dds/src/security.hpp: DDS Security on a participant, as SROS2 configures rmw_fastrtps.
//
// Participant properties (Fast DDS 2.9 documentation, "Security" and "PropertyPolicyQos":
// security.rst / auth_plugin.rst / access_plugin.rst / crypto_plugin.rst; the plugins are the
// builtin ones of OMG DDS Security 1.1: DDS:Auth:PKI-DH (9.3), DDS:Access:Permissions (9.4),
// DDS:Crypto:AES-GCM-GMAC (9.5)); file values are "file://<absolute path>":
//   dds.sec.auth.plugin                                          builtin.PKI-DH
//   dds.sec.auth.builtin.PKI-DH.identity_ca                      enclave's identity_ca.cert.pem
//   dds.sec.auth.builtin.PKI-DH.identity_certificate             enclave's cert.pem
//   dds.sec.auth.builtin.PKI-DH.private_key                      enclave's key.pem
//   dds.sec.access.plugin                                        builtin.Access-Permissions
//   dds.sec.access.builtin.Access-Permissions.permissions_ca     enclave's permissions_ca.cert.pem
//   dds.sec.access.builtin.Access-Permissions.governance         enclave's governance.p7s
//   dds.sec.access.builtin.Access-Permissions.permissions        enclave's permissions.p7s
//   dds.sec.crypto.plugin                                        builtin.AES-GCM-GMAC
#pragma once

#include <string>

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include "dds_bridge.hpp"

namespace tern::core::ddsi {

/// Checks the enclave's files (keystore_check.hpp) and sets the properties above on `q`.
/// Throws DdsError naming the first missing or bad file.
void apply_security(eprosima::fastdds::dds::DomainParticipantQos& q, const DdsSecurity& s);

/// The participant's user data as rmw_fastrtps writes it: "enclave=/<enclave>;" ("enclave=/;"
/// without security).
std::string enclave_user_data(const DdsOptions& o);

}  // namespace tern::core::ddsi
