// core/apps/dds/src/keystore_documents.hpp: the governance and permissions documents of a tern
// keystore (OMG DDS Security 1.1, 9.4.1.2 "Domain Governance Document" and 9.4.1.3 "DomainParticipant
// Permissions Document"), in the element order Fast DDS 2.9's GovernanceParser and
// PermissionsParser require (the same as SROS2's templates).
#pragma once

#include <string>

namespace tern::core::ddsi {

/// The lowest and highest DDS domain id tern uses (dds.domain: 0..232).
inline constexpr int kFirstDomain = 0, kLastDomain = 232;

/// Governance for domains kFirstDomain..kLastDomain: allow_unauthenticated_participants false,
/// enable_join_access_control true, discovery, liveliness and RTPS protection ENCRYPT; one topic
/// rule for "*" with discovery/liveliness protection, read/write access control, metadata and
/// data protection ENCRYPT.
std::string governance_xml();

/// Permissions of subject "CN=<name>": publish and subscribe on every topic ("*") of domains
/// kFirstDomain..kLastDomain from `not_before` to `not_after` ("YYYY-MM-DDThh:mm:ss", UTC);
/// everything else denied.
std::string permissions_xml(const std::string& name, const std::string& not_before, const std::string& not_after);

}  // namespace tern::core::ddsi
