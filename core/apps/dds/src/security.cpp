// core/apps/dds/src/security.cpp: the security properties of a participant (see security.hpp).
#include "security.hpp"

#include "keystore_check.hpp"

namespace tern::core::ddsi {

namespace {
/// "file://" + an absolute path: Fast DDS reads what follows "file://" as a file name (PKIDH.cpp, Permissions.cpp)
std::string uri(const std::filesystem::path& p) { return "file://" + std::filesystem::absolute(p).lexically_normal().string(); }
}  // namespace

void apply_security(eprosima::fastdds::dds::DomainParticipantQos& q, const DdsSecurity& s) {
  const EnclaveFiles f = enclave_files(s);
  check_enclave(s, f);
  auto& props = q.properties().properties();
  const std::string auth = "dds.sec.auth.builtin.PKI-DH.";
  const std::string access = "dds.sec.access.builtin.Access-Permissions.";
  props.emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
  props.emplace_back(auth + "identity_ca", uri(f.identity_ca));
  props.emplace_back(auth + "identity_certificate", uri(f.certificate));
  props.emplace_back(auth + "private_key", uri(f.private_key));
  props.emplace_back("dds.sec.access.plugin", "builtin.Access-Permissions");
  props.emplace_back(access + "permissions_ca", uri(f.permissions_ca));
  props.emplace_back(access + "governance", uri(f.governance));
  props.emplace_back(access + "permissions", uri(f.permissions));
  props.emplace_back("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
}

std::string enclave_user_data(const DdsOptions& o) { return "enclave=/" + (o.security ? o.security->enclave : std::string()) + ";"; }

}  // namespace tern::core::ddsi
