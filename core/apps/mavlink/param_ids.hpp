// core/apps/mavlink/param_ids.hpp: tern's parameters ("instance.param") as MAVLink parameters:
// 16-character ids and REAL32/INT32/UINT8 values (PARAM_VALUE, https://mavlink.io/en/services/parameter.html).
//
// Ids: a qualified name of at most 16 characters is its own id ("slc.roll_kp"). A longer one is
// shortened deterministically: its first 11 characters, '~', and 4 hex digits of the FNV-1a 64 hash
// (tern/fnv1a.hpp) (true offset basis) of the whole name, its four 16-bit words XORed ("estimator_ekf.gyro_noise" ->
// "estimator_e~" + hash). Should two names still meet, the later one (in the host's parameter
// order) takes the next hash of "name#k" (k = 1, 2, ...); the table is the same for the same
// mission. The table is printed at the endpoint's start (shortened ids only) and in
// docs/ground-station.md's rule.
//
// Types: a real parameter is MAV_PARAM_TYPE_REAL32 (a double sent as float: 7 digits), an integer
// MAV_PARAM_TYPE_INT32 (its value as a float, as MAVLink's PARAM_VALUE carries every type in a
// float: exact up to 2^24), a boolean MAV_PARAM_TYPE_UINT8 (0 or 1). Text and vector parameters
// have no MAVLink form and are left out of the list (tern params and the console show them).
//
// Errors: none thrown here; a value's own checks happen in Host::request_param.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "tern/param.hpp"

namespace tern::core::mavlink {

/// One parameter as the GCS sees it.
struct MavParam {
  std::string id;         ///< <= 16 chars
  std::string qualified;  ///< "instance.param"
  ParamKind kind = ParamKind::real;
  std::uint8_t mav_type = 0;  ///< MAV_PARAM_TYPE_*
};

/// The parameters of a mission as MAVLink parameters, in the host's order (the index is
/// PARAM_VALUE's param_index).
class ParamTable {
 public:
  /// `params`: (qualified name, kind) in the host's order; text and vector ones are skipped.
  explicit ParamTable(const std::vector<std::pair<std::string, ParamKind>>& params);
  const std::vector<MavParam>& params() const { return params_; }
  /// The index of the parameter with MAVLink id `id` (compared up to 16 chars), or nullopt.
  std::optional<std::size_t> find(const std::string& id) const;
  /// The shortened ones: (qualified, id).
  std::vector<std::pair<std::string, std::string>> shortened() const;

 private:
  std::vector<MavParam> params_;
  std::map<std::string, std::size_t> by_id_;
};

/// The id rule above for one name (`salt` 0: the first try).
std::string shorten_param_id(const std::string& qualified, int salt = 0);

/// The value sent in PARAM_VALUE's float for a tern value of kind `kind`.
float to_mav_value(const tern::ParamValue& v);
/// PARAM_SET's float as a tern value of kind `kind`: a real as the shortest decimal that reads back
/// as that float, an integer or boolean rounded to the nearest.
tern::ParamValue from_mav_value(float v, ParamKind kind);

}  // namespace tern::core::mavlink
