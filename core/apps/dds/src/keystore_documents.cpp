// core/apps/dds/src/keystore_documents.cpp: governance and permissions XML (see keystore_documents.hpp).
#include "keystore_documents.hpp"

#include <fmt/format.h>

namespace tern::core::ddsi {

namespace {
constexpr const char* kGovernanceSchema = "http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd";
constexpr const char* kPermissionsSchema = "http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd";

std::string domains() {
  return fmt::format("<domains><id_range><min>{}</min><max>{}</max></id_range></domains>", kFirstDomain, kLastDomain);
}
}  // namespace

std::string governance_xml() {
  return fmt::format(R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="{}">
  <domain_access_rules>
    <domain_rule>
      {}
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>ENCRYPT</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
)",
                     kGovernanceSchema, domains());
}

std::string permissions_xml(const std::string& name, const std::string& not_before, const std::string& not_after) {
  return fmt::format(R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="{}">
  <permissions>
    <grant name="/{}">
      <subject_name>CN={}</subject_name>
      <validity>
        <not_before>{}</not_before>
        <not_after>{}</not_after>
      </validity>
      <allow_rule>
        {}
        <publish><topics><topic>*</topic></topics></publish>
        <subscribe><topics><topic>*</topic></topics></subscribe>
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
)",
                     kPermissionsSchema, name, name, not_before, not_after, domains());
}

}  // namespace tern::core::ddsi
