// core/apps/mavlink/component_metadata.hpp: what QGroundControl reads to show tern's parameters
// with their descriptions, units, ranges and groups (the component metadata protocol,
// https://mavlink.io/en/services/component_information.html): COMPONENT_METADATA's URI names the
// general metadata file, which names the parameter metadata file; both are served over MAVLink FTP
// (mavlink_ftp.hpp). Pure: built from the host's parameters once, when the link starts.
//
// Schemas: github.com/mavlink/mavlink component_metadata/general.schema.json (version 1,
// metadataTypes [{type, uri}]) and parameter.schema.json (version 3, parameters [{name, type,
// shortDesc, longDesc, units, default, min, max, group, category, rebootRequired}]). Each
// parameter the MAVLink endpoint lists (param_ids.hpp: numbers and booleans) is described under
// its MAVLink id: shortDesc is ParamSpec::description, units ParamSpec::unit, min and max the
// declared range (left out when unbounded), default the plugin's default, group the instance
// ("slc"), longDesc the full tern name and, for a start-only one, when it takes effect;
// rebootRequired marks a start-only parameter (tern reads it when a flight starts).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "mavlink/param_ids.hpp"
#include "tern/param.hpp"

namespace tern::core::mavlink {

inline constexpr const char* kGeneralMetadataFile = "general.json";
inline constexpr const char* kParameterMetadataFile = "parameters.json";
/// COMPONENT_METADATA's uri: the general metadata file over MAVLink FTP
inline constexpr const char* kGeneralMetadataUri = "mftp://general.json";
/// COMP_METADATA_TYPE (common.xml)
inline constexpr int COMP_METADATA_TYPE_GENERAL = 0, COMP_METADATA_TYPE_PARAMETER = 1;

struct MetadataFiles {
  std::string general;     ///< general.json
  std::string parameters;  ///< parameters.json
};

/// The two files for the parameters of `table` (the MAVLink ids) described by `params` (the
/// host's: qualified name -> parameter).
MetadataFiles component_metadata(const ParamTable& table, const std::vector<std::pair<std::string, const ParamBase*>>& params);

}  // namespace tern::core::mavlink
