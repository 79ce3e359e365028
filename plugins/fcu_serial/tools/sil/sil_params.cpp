// sil/sil_params.cpp: --params FILE (YAML NAME: value) written into the firmware's flash before
// it boots, as a ground station sets and saves parameters on a board: a firmware instance boots
// on the board (reading the flash, or taking its defaults and writing them: param.cpp
// Params::init), each value is set through the firmware's own Params::set_param_int/float
// by the type the firmware declares for the name, then Params::write saves the block. That
// instance is discarded before the flight's firmware boots from the flash it wrote.
#include <array>
#include <cmath>
#include <cstring>

#include <yaml-cpp/yaml.h>

#include "mavlink_adapter.hpp"
#include "rosflight.h"
#include "sil.hpp"

namespace tern::fcu::sil {

namespace {
namespace rf = rosflight_firmware;

void set_one(rf::Params& params, const std::string& file, const std::string& name, const YAML::Node& value) {
  std::array<char, rf::Params::PARAMS_NAME_LENGTH> id_name{};  // MAVLink's param_id: up to 16 characters
  std::uint16_t id = rf::PARAMS_COUNT;
  if (name.size() <= id_name.size()) {
    std::memcpy(id_name.data(), name.data(), name.size());
    id = params.lookup_param_id(id_name.data());
  }
  if (id >= rf::PARAMS_COUNT) throw std::runtime_error("--params " + file + ": " + name + " is not a parameter of this firmware");
  const bool is_int = params.get_param_type(id) == rf::PARAM_TYPE_INT32;
  const auto bad = [&](const std::string& what) {
    return std::runtime_error("--params " + file + ": " + name + ": " + what + " is not " + (is_int ? "an int32" : "a finite number"));
  };
  if (!value.IsScalar()) throw bad(value.IsNull() ? "an empty value" : "a list or map");
  try {
    if (is_int) {
      params.set_param_int(id, value.as<std::int32_t>());
    } else {
      const float v = value.as<float>();
      if (!std::isfinite(v)) throw bad("'" + value.Scalar() + "'");
      params.set_param_float(id, v);
    }
  } catch (const YAML::Exception&) {
    throw bad("'" + value.Scalar() + "'");
  }
}
}  // namespace

void Sil::upload_params() {
  const std::string& file = o_.world.params;
  if (file.empty()) return;
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(file);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("--params " + file + ": " + e.what());
  }
  if (!doc.IsMap()) throw std::runtime_error("--params " + file + ": expected a map NAME: value");
  rf::MavlinkAdapter adapter(board_);
  rf::ROSflight fw(board_, adapter);
  fw.init();
  for (const auto& kv : doc) set_one(fw.params_, file, kv.first.as<std::string>(), kv.second);
  if (!fw.params_.write()) throw std::runtime_error("--params " + file + ": the firmware could not write its flash " + board_.flash_file());
  board_.take_sent();  // that instance never reached the link
}

}  // namespace tern::fcu::sil
