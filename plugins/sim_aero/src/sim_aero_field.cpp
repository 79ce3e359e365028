// SimAero: the world's magnetic field: the mag_* settings nobody set, from the model at the
// world's date and place (see sim_aero_plugin.hpp).
#include "sim_aero_plugin.hpp"

namespace tern::sim_aero {

bool SimAero::is_field_row(const SensorReal& r) {
  return r.field == &sim::SensorParams::mag_declination || r.field == &sim::SensorParams::mag_inclination ||
         r.field == &sim::SensorParams::mag_intensity;
}

bool SimAero::is_origin_row(const SensorReal& r) {
  return r.field == &sim::SensorParams::origin_lat || r.field == &sim::SensorParams::origin_lon ||
         r.field == &sim::SensorParams::origin_alt;
}

double SimAero::world_date() const {
  try {
    return tern::decimal_year(date_());
  } catch (const std::invalid_argument& e) {
    throw ParamError("parameter '" + context().instance_name() + ".date': " + e.what());
  }
}

void SimAero::sync_world_field() {
  const sim::SensorParams p = sim::with_earth_field(sensor_params());
  const bool was_applying = std::exchange(applying_profile_, true);
  for (std::size_t i = 0; i < std::size(kSensorReals); ++i) {
    if (is_field_row(kSensorReals[i]) && !set_explicitly_.count(&sensor_reals_[i])) sensor_reals_[i].set(p.*kSensorReals[i].field);
  }
  applying_profile_ = was_applying;
}

void SimAero::report_earth_field() {
  const tern::MagneticField& m = f_.sensors->earth_field();
  const auto& p = f_.sensors->params();
  std::string source = fmt::format("{} at {:.5f}, {:.5f} on {}", m.model, p.origin_lat, p.origin_lon, date_());
  for (std::size_t i = 0; i < std::size(kSensorReals); ++i)
    if (is_field_row(kSensorReals[i]) && set_explicitly_.count(&sensor_reals_[i])) source += fmt::format("; {} set", kSensorReals[i].name);
  if (m.model == "mag_* settings") source = "mag_declination, mag_inclination, mag_intensity set";
  log().info("Earth's field: declination {:.3f} deg, inclination {:.3f} deg, intensity {:.0f} nT ({})", m.declination / tern::kRadPerDeg,
             m.inclination / tern::kRadPerDeg, m.intensity * 1e9, source);
  if (m.extrapolated) log().warn("the world's date {} is outside {}'s span: its field is extrapolated", date_(), m.model);
}

}  // namespace tern::sim_aero
