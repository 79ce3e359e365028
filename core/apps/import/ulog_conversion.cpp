// core/apps/import/ulog_conversion.cpp: the handlers of `tern import ulog`'s conversion pass, one per
// output and source topic (the mapping, times and units: ulog_import.hpp).
#include "import/ulog_conversion.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace tern::core::ulog_import {

namespace {

using ulog::DataMessage;
using ulog::Field;
using ulog::Subscription;

constexpr std::int64_t kInvalidRelative = 0x7fffffff;  // PX4's RELATIVE_TIMESTAMP_INVALID
constexpr double kGaussToTesla = 1e-4;

}  // namespace

Survey survey(const std::filesystem::path& file) {
  ulog::Reader r(file);
  Survey s;
  ulog::DataHandler h;
  h.on_data = [&](const DataMessage& d) {
    const Subscription& sub = d.subscription();
    if (sub.multi_id != 0) return;
    ++s.rows[sub.name];
    if (sub.name != "sensor_combined") return;
    if (const Field* f = sub.field("magnetometer_timestamp_relative"); f && d.integer(*f) != kInvalidRelative) ++s.combined_mag;
    if (const Field* f = sub.field("baro_timestamp_relative"); f && d.integer(*f) != kInvalidRelative) ++s.combined_baro;
  };
  r.read_data(h);
  return s;
}

bool has_fields(const std::map<std::string, ulog::Format>& formats, const std::string& topic, std::initializer_list<const char*> names) {
  if (!formats.count(topic)) return false;
  const Subscription sub(topic, 0, 0, formats);
  for (const char* n : names)
    if (!sub.field(n)) return false;
  return true;
}

void Conversion::add_imu() {
  factories["sensor_combined"].push_back([this](const Fields& f) -> Handler {
    const auto gyro = f.vec("gyro_rad"), accel = f.vec("accelerometer_m_s2");
    const Field* rel = f.opt("accelerometer_timestamp_relative");
    return [this, gyro, accel, rel](const DataMessage& d) {
      const auto t = stamp(static_cast<std::int64_t>(d.timestamp()));
      if (!t) return;
      msg::Imu m;
      m.stamp = *t;
      for (int i = 0; i < 3; ++i) m.gyro[i] = d.value(*gyro[i]), m.accel[i] = d.value(*accel[i]);
      if (!m.gyro.allFinite() || !m.accel.allFinite()) return void(++nan_rows_);
      const std::int64_t relative = rel ? d.integer(*rel) : kInvalidRelative;
      if (relative != kInvalidRelative && relative != std::numeric_limits<std::int64_t>::min())  // |INT64_MIN| is no int64
        max_accel_relative_us_ = std::max(max_accel_relative_us_, std::abs(relative));
      imu_intervals.add(m.stamp);
      imu_.push(m);
    };
  });
}

void Conversion::write_mag(Nanos t, double x, double y, double z) {
  msg::Mag m;
  m.stamp = t;
  m.field = Eigen::Vector3d(x, y, z) * kGaussToTesla;
  if (!m.field.allFinite()) return void(++nan_rows_);
  mag_.push(m);
}

void Conversion::add_mag(const std::string& source) {
  factories[source].push_back([this, source](const Fields& f) -> Handler {
    if (source == "sensor_combined") {
      const auto ga = f.vec("magnetometer_ga");
      const Field& rel = f.need("magnetometer_timestamp_relative");
      return [this, ga, &rel](const DataMessage& d) {
        const std::int64_t r = d.integer(rel);
        if (r == kInvalidRelative) return;
        const auto t = stamp(offset_us(d.timestamp(), r));
        if (!t || *t <= last_combined_mag_) return;  // the same sample, repeated in every sensor_combined row
        last_combined_mag_ = *t;
        write_mag(*t, d.value(*ga[0]), d.value(*ga[1]), d.value(*ga[2]));
      };
    }
    const bool raw = source == "sensor_mag";
    const std::array<const Field*, 3> ga =
        raw ? std::array<const Field*, 3>{&f.need("x"), &f.need("y"), &f.need("z")} : f.vec("magnetometer_ga");
    const Field* ts = f.opt("timestamp_sample");
    return [this, ga, ts](const DataMessage& d) {
      if (const auto t = sample_stamp(d, ts)) write_mag(*t, d.value(*ga[0]), d.value(*ga[1]), d.value(*ga[2]));
    };
  });
}

void Conversion::add_baro(const std::string& source) {
  factories[source].push_back([this, source](const Fields& f) -> Handler {
    const Field* pressure = f.first_of({"baro_pressure_pa", "pressure"});
    const Field* height = f.opt("baro_alt_meter");
    const Field* temp = f.first_of({"baro_temp_celcius", "temperature"});
    const Field* rel = source == "sensor_combined" ? &f.need("baro_timestamp_relative") : nullptr;
    const Field* ts = f.opt("timestamp_sample");
    const bool use_height = source == "sensor_combined" || !pressure;
    return [this, pressure, height, temp, rel, ts, use_height, hpa = source == "sensor_baro"](const DataMessage& d) {
      std::optional<Nanos> t;
      if (rel) {
        const std::int64_t r = d.integer(*rel);
        if (r == kInvalidRelative) return;
        t = stamp(offset_us(d.timestamp(), r));
        if (!t || *t <= last_combined_baro_) return;
        last_combined_baro_ = *t;
      } else {
        t = sample_stamp(d, ts);
      }
      if (!t) return;
      msg::Baro m;
      m.stamp = *t;
      m.pressure = use_height ? isa_pressure_from_height(d.value(*height)) : d.value(*pressure);
      if (hpa && m.pressure < 2000.0) m.pressure *= 100.0;  // sensor_baro in hPa (older PX4) or Pa
      m.temperature = kelvin_from_celsius(temp ? d.value(*temp) : std::nan(""), no_temperature_);
      if (!std::isfinite(m.pressure)) return void(++nan_rows_);
      baro_.push(m);
    };
  });
}

void Conversion::add_diff_pressure(const std::string& source) {
  factories[source].push_back([this, source](const Fields& f) -> Handler {
    const bool eas = source == "airspeed";
    const Field* value =
        eas ? &f.need("indicated_airspeed_m_s")
            : f.first_of({"differential_pressure_pa", "differential_pressure_filtered_pa", "differential_pressure_raw_pa"});
    if (!value) throw std::out_of_range("topic '" + source + "' has no differential_pressure_pa/_filtered_pa/_raw_pa field");
    const Field* temp = f.first_of({"temperature", "air_temperature_celsius"});
    const Field* ts = f.opt("timestamp_sample");
    return [this, value, temp, ts, eas](const DataMessage& d) {
      const auto t = sample_stamp(d, ts);
      if (!t) return;
      msg::DiffPressure m;
      m.stamp = *t;
      m.pressure = eas ? diff_pressure_from_eas(d.value(*value)) : d.value(*value);
      m.temperature = kelvin_from_celsius(temp ? d.value(*temp) : std::nan(""), no_temperature_);
      if (!std::isfinite(m.pressure)) return void(++nan_rows_);
      dp_.push(m);
    };
  });
}

void Conversion::add_gnss(const std::string& source) {
  factories[source].push_back([this](const Fields& f) -> Handler {
    const Field* lat = f.first_of({"lat", "latitude_deg"});
    const Field* lon = f.first_of({"lon", "longitude_deg"});
    const Field* alt = f.first_of({"alt", "altitude_msl_m"});
    if (!lat || !lon || !alt)
      throw std::out_of_range("topic '" + f.sub.name + "' has no lat/lon/alt (nor latitude_deg/longitude_deg/altitude_msl_m)");
    const auto vel = std::array<const Field*, 3>{&f.need("vel_n_m_s"), &f.need("vel_e_m_s"), &f.need("vel_d_m_s")};
    const Field *fix = &f.need("fix_type"), *sats = f.opt("satellites_used"), *eph = f.opt("eph"), *epv = f.opt("epv");
    const Field *sacc = f.opt("s_variance_m_s"), *ts = f.opt("timestamp_sample"), *utc = f.opt("time_utc_usec");
    const Field *hdop = f.opt("hdop"), *vdop = f.opt("vdop");
    const Field *ned_valid = f.opt("vel_ned_valid"), *speed = f.opt("vel_m_s"), *course = f.opt("cog_rad");
    const Nanos delay = static_cast<Nanos>(std::llround(param("EKF2_GPS_DELAY").value_or(0.0) * 1e6));
    return [=](const DataMessage& d) {
      const auto t = stamp(static_cast<std::int64_t>(d.timestamp()));
      if (!t) return;
      msg::Gnss m;
      m.stamp = *t;
      const bool scaled = lat->type == ulog::BaseType::int32;  // 1e-7 deg and mm, else double deg and m
      m.lat = d.value(*lat) * (scaled ? 1e-7 : 1.0);
      m.lon = d.value(*lon) * (scaled ? 1e-7 : 1.0);
      m.alt = d.value(*alt) * (alt->type == ulog::BaseType::int32 ? 1e-3 : 1.0);
      m.vel = {d.value(*vel[0]), d.value(*vel[1]), d.value(*vel[2])};
      if (ned_valid && speed && course && d.value(*ned_valid) == 0.0) {  // speed and course only
        m.vel.x() = d.value(*speed) * std::cos(d.value(*course));
        m.vel.y() = d.value(*speed) * std::sin(d.value(*course));
        ++course_velocity_;
      }
      m.fix_type = px4_fix_type(static_cast<int>(d.integer(*fix)));
      m.num_sats = sats ? static_cast<std::uint8_t>(d.integer(*sats)) : 0;
      m.h_acc = eph ? d.value(*eph) : 0.0;
      m.v_acc = epv ? d.value(*epv) : 0.0;
      m.s_acc = sacc ? d.value(*sacc) : 0.0;
      m.hdop = hdop ? d.value(*hdop) : 0.0;
      m.vdop = vdop ? d.value(*vdop) : 0.0;
      if (ts) {  // 0: unknown (before the log's start, or no int64 ns time: never an overflow)
        const std::int64_t sample = d.integer(*ts);
        Nanos valid = 0;
        if (sample > origin() && sample - origin() <= std::numeric_limits<std::int64_t>::max() / 1000 &&
            !__builtin_sub_overflow((sample - origin()) * 1000, delay, &valid))
          m.time_of_validity = std::max<Nanos>(0, valid);
      }
      if (!std::isfinite(m.lat) || !std::isfinite(m.lon) || !std::isfinite(m.alt) || !m.vel.allFinite() || !std::isfinite(m.h_acc) ||
          !std::isfinite(m.v_acc) || !std::isfinite(m.s_acc) || !std::isfinite(m.hdop) || !std::isfinite(m.vdop))
        return void(++nan_rows_);
      if (date.empty() && utc && m.fix_type >= msg::FixType::fix_2d && d.integer(*utc) > 1'000'000'000'000'000)
        date = iso_date_from_utc_usec(static_cast<std::uint64_t>(d.integer(*utc)));
      gnss_intervals.add(m.stamp);
      gnss_.push(m);
    };
  });
}

void Conversion::add_attitude(const std::string& source) {
  factories[source].push_back([this](const Fields& f) -> Handler {
    const std::array<const Field*, 4> q{&f.need("q[0]"), &f.need("q[1]"), &f.need("q[2]"), &f.need("q[3]")};
    return [this, q](const DataMessage& d) {
      const auto t = stamp(static_cast<std::int64_t>(d.timestamp()));
      if (!t) return;
      const Euler e = euler_from_px4_quaternion(d.value(*q[0]), d.value(*q[1]), d.value(*q[2]), d.value(*q[3]));
      msg::Reference m;
      m.stamp = *t;
      m.phi = e.phi, m.theta = e.theta, m.psi = e.psi;
      ref_.push(m);
    };
  });
}

/// lat/lon/alt from vehicle_global_position, or from vehicle_local_position's x (north), y (east), z (down)
/// about its reference (ref_lat/ref_lon in deg, ref_alt in m AMSL), by PX4's own projection (px4_reproject).
void Conversion::add_position(const std::string& source) {
  factories[source].push_back([this, local = source == "vehicle_local_position"](const Fields& f) -> Handler {
    if (!local) {
      const Field *lat = &f.need("lat"), *lon = &f.need("lon"), *alt = &f.need("alt");
      return [this, lat, lon, alt](const DataMessage& d) {
        const auto t = stamp(static_cast<std::int64_t>(d.timestamp()));
        if (!t) return;
        msg::Reference m;
        m.stamp = *t;
        m.lat = d.value(*lat), m.lon = d.value(*lon), m.alt = d.value(*alt);
        ref_.push(m);
      };
    }
    const Field *x = &f.need("x"), *y = &f.need("y"), *z = &f.need("z"), *rlat = &f.need("ref_lat"), *rlon = &f.need("ref_lon");
    const Field *ralt = &f.need("ref_alt"), *xy_global = &f.need("xy_global"), *z_global = &f.need("z_global");
    return [=](const DataMessage& d) {
      const auto t = stamp(static_cast<std::int64_t>(d.timestamp()));
      if (!t || d.value(*xy_global) == 0.0) return;
      const double scale = rlat->type == ulog::BaseType::int32 ? 1e-7 : 1.0;
      msg::Reference m;
      m.stamp = *t;
      const LatLon p = px4_reproject(d.value(*rlat) * scale, d.value(*rlon) * scale, d.value(*x), d.value(*y));
      m.lat = p.lat, m.lon = p.lon;
      if (d.value(*z_global) != 0.0) m.alt = d.value(*ralt) - d.value(*z);
      ref_.push(m);
    };
  });
}

void Conversion::add_velocity(const std::string& source) {
  factories[source].push_back([this, local = source == "vehicle_local_position"](const Fields& f) -> Handler {
    const auto v = local ? std::array<const Field*, 3>{&f.need("vx"), &f.need("vy"), &f.need("vz")}
                         : std::array<const Field*, 3>{&f.need("vel_n"), &f.need("vel_e"), &f.need("vel_d")};
    const Field* valid = local ? f.opt("v_xy_valid") : nullptr;
    return [this, v, valid](const DataMessage& d) {
      const auto t = stamp(static_cast<std::int64_t>(d.timestamp()));
      if (!t || (valid && d.value(*valid) == 0.0)) return;
      msg::Reference m;
      m.stamp = *t;
      m.v_n = d.value(*v[0]), m.v_e = d.value(*v[1]), m.v_d = d.value(*v[2]);
      ref_.push(m);
    };
  });
}

void Conversion::add_wind(const std::string& source) {
  factories[source].push_back([this](const Fields& f) -> Handler {
    const Field *n = &f.need("windspeed_north"), *e = &f.need("windspeed_east");
    return [this, n, e](const DataMessage& d) {
      const auto t = stamp(static_cast<std::int64_t>(d.timestamp()));
      if (!t) return;
      msg::Reference m;
      m.stamp = *t;
      m.w_n = d.value(*n), m.w_e = d.value(*e);
      ref_.push(m);
    };
  });
}

void Conversion::add_actuators(const std::string& source, const CommandMapping& mapping) {
  actuator_source_ = source;
  factories[source].push_back([this, mapping](const Fields& f) -> Handler {
    const std::array<const Field*, 4> u{&f.need("control[0]"), &f.need("control[1]"), &f.need("control[2]"), &f.need("control[3]")};
    const Field* ts = f.opt("timestamp_sample");
    return [this, u, ts, mapping](const DataMessage& d) {
      const auto t = stamp(static_cast<std::int64_t>(d.timestamp()));
      if (!t) return;
      const NormalisedCommand c{d.value(*u[0]), d.value(*u[1]), d.value(*u[2]), d.value(*u[3])};
      if (!std::isfinite(c.roll) || !std::isfinite(c.pitch) || !std::isfinite(c.yaw) || !std::isfinite(c.throttle))
        return void(++nan_actuator_rows_);
      std::int64_t lag = 0, sum = 0;  // the gyro sample the command was computed from (a lag no int64 holds: none)
      if (ts && d.integer(*ts) > 0 && !__builtin_sub_overflow(offset_us(d.timestamp(), 0), d.integer(*ts), &lag) &&
          !__builtin_add_overflow(control_latency_sum_us_, lag, &sum)) {
        control_latency_sum_us_ = sum, ++control_latency_count_;
        control_latency_max_us_ = std::max(control_latency_max_us_, lag);
      }
      const msg::Actuators a = actuators_from_normalised(*t, c, mapping);
      actuator_intervals.add(a.stamp);
      act_.push(a);
    };
  });
}

void Conversion::add_servo_actuators(const std::array<std::vector<double>, 3>& effectiveness, const std::vector<int>& motors,
                                     const CommandMapping& mapping) {
  actuator_source_ = "actuator_servos";
  if (!motors.empty())
    factories["actuator_motors"].push_back([this, motors](const Fields& f) -> Handler {
      std::vector<const Field*> u;
      for (int i : motors) u.push_back(&f.need(fmt::format("control[{}]", i)));
      return [this, u](const DataMessage& d) {
        double sum = 0.0;
        for (const Field* m : u) sum += d.value(*m);
        const double mean = sum / static_cast<double>(u.size());
        if (std::isfinite(mean))
          motor_throttle_ = std::clamp(mean, 0.0, 1.0);  // NaN: disarmed (the motors stopped)
        else
          motor_throttle_ = 0.0;
      };
    });
  factories["actuator_servos"].push_back([this, effectiveness, mapping](const Fields& f) -> Handler {
    std::vector<const Field*> s;
    for (std::size_t i = 0; i < effectiveness[0].size(); ++i) s.push_back(&f.need(fmt::format("control[{}]", i)));
    return [this, s, effectiveness, mapping](const DataMessage& d) {
      const auto t = stamp(static_cast<std::int64_t>(d.timestamp()));
      if (!t) return;
      std::array<double, 3> u{};
      for (std::size_t axis = 0; axis < 3; ++axis) {
        double sum = 0.0, weight = 0.0;
        for (std::size_t i = 0; i < s.size(); ++i) {
          const double e = effectiveness[axis][i];
          if (e == 0.0) continue;
          sum += e * d.value(*s[i]), weight += std::abs(e);
        }
        u[axis] = weight > 0.0 ? sum / weight : 0.0;
      }
      if (!std::isfinite(u[0]) || !std::isfinite(u[1]) || !std::isfinite(u[2])) return void(++nan_actuator_rows_);  // disarmed
      const msg::Actuators a = actuators_from_normalised(*t, {u[0], u[1], u[2], motor_throttle_}, mapping);
      actuator_intervals.add(a.stamp);
      act_.push(a);
    };
  });
}

void Conversion::finish(const std::string& file, std::vector<std::string>& notes) {
  imu_.flush(), mag_.flush(), baro_.flush(), dp_.flush(), gnss_.flush(), ref_.flush(), act_.flush();
  const std::uint64_t late =
      imu_.dropped() + mag_.dropped() + baro_.dropped() + dp_.dropped() + gnss_.dropped() + ref_.dropped() + act_.dropped();
  auto warn = [&](std::uint64_t n, const std::string& what) {
    if (n) report_.warnings.push_back(fmt::format("{}: {} {}", file, n, what));
  };
  warn(before_start_, "row(s) stamped before the log's start timestamp (stale samples published before logging began): dropped");
  warn(late, "row(s) more than 1 s out of time order within their topic: dropped");
  warn(nan_rows_, "sensor row(s) with a NaN or infinite value: dropped");
  warn(nan_actuator_rows_, actuator_source_ + " row(s) with a NaN or infinite control (disarmed outputs): dropped");
  if (control_latency_count_)
    notes.push_back(
        fmt::format("actuators: {} published {:.1f} ms (mean; at most {:.1f} ms) after the gyro sample it was computed from "
                    "(timestamp - timestamp_sample)",
                    actuator_source_, 1e-3 * static_cast<double>(control_latency_sum_us_) / static_cast<double>(control_latency_count_),
                    1e-3 * static_cast<double>(control_latency_max_us_)));
  warn(course_velocity_, "GNSS row(s) without a valid NED velocity (vel_ned_valid 0): north/east from vel_m_s and cog_rad");
  if (no_temperature_)
    notes.push_back(
        fmt::format("{} baro/diff_pressure rows without a usable temperature: {:.2f} K written", no_temperature_, msg::Baro{}.temperature));
  notes.push_back(fmt::format("imu temperature: not in sensor_combined; the message default {:.2f} K is written", msg::Imu{}.temperature));
  if (max_accel_relative_us_ > 0)
    notes.push_back(fmt::format("imu stamp: sensor_combined.timestamp (the gyro's); the accelerometer's differs by up to {} us",
                                max_accel_relative_us_));
}

}  // namespace tern::core::ulog_import
