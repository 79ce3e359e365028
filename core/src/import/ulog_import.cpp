// core/src/import/ulog_import.cpp: `tern import ulog`, the conversion of PX4 topics into the sensor
// log's (the mapping, times and units: ulog_import.hpp; the reader: ulog_reader.hpp).
#include "import/ulog_import.hpp"

#include <cmath>
#include <ctime>
#include <map>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "import/import_support.hpp"
#include "import/importers.hpp"
#include "import/ulog_reader.hpp"
#include "tern/msg/estimator.hpp"

namespace tern::core {

namespace ulog_import {

msg::FixType px4_fix_type(int px4) {
  if (px4 == 2) return msg::FixType::fix_2d;
  if (px4 >= 3 && px4 <= 6) return msg::FixType::fix_3d;
  if (px4 == 7 || px4 == 8) return msg::FixType::dead_reckoning;
  return msg::FixType::none;
}

Euler euler_from_px4_quaternion(double w, double x, double y, double z) {
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  w /= n, x /= n, y /= n, z /= n;
  const double phi = std::atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y));
  const double theta = std::asin(std::clamp(2.0 * (w * y - z * x), -1.0, 1.0));
  const double psi = std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
  return {phi, theta, psi};
}

LatLon px4_reproject(double ref_lat_deg, double ref_lon_deg, double north_m, double east_m) {
  constexpr double kRadius = 6371000.0;  // PX4's CONSTANTS_RADIUS_OF_EARTH
  constexpr double kDeg = M_PI / 180.0;
  const double x = north_m / kRadius, y = east_m / kRadius, c = std::hypot(x, y);
  if (c == 0.0) return {ref_lat_deg, ref_lon_deg};
  const double lat0 = ref_lat_deg * kDeg, sin_c = std::sin(c), cos_c = std::cos(c);
  const double lat = std::asin(cos_c * std::sin(lat0) + x * sin_c * std::cos(lat0) / c);
  const double lon = ref_lon_deg * kDeg + std::atan2(y * sin_c, c * std::cos(lat0) * cos_c - x * std::sin(lat0) * sin_c);
  return {lat / kDeg, lon / kDeg};
}

std::string iso_date_from_utc_usec(std::uint64_t utc_usec) {
  const std::time_t secs = static_cast<std::time_t>(utc_usec / 1000000);
  std::tm tm{};
  gmtime_r(&secs, &tm);
  return fmt::format("{:04d}-{:02d}-{:02d}", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday);
}

}  // namespace ulog_import

namespace {

namespace fs = std::filesystem;
using namespace ulog_import;
using ulog::DataMessage;
using ulog::Field;
using ulog::Subscription;

constexpr std::int64_t kInvalidRelative = 0x7fffffff;  // PX4's RELATIVE_TIMESTAMP_INVALID
constexpr Nanos kWindow = kNanosPerSecond;
constexpr double kGaussToTesla = 1e-4;
constexpr double kCelsiusToKelvin = 273.15;
constexpr double kNoTemperature = 288.15;  // the message default, written when the log has none

/// Which topics (multi-instance 0) hold data, and whether old sensor_combined carries mag/baro samples.
struct Survey {
  std::map<std::string, std::uint64_t> rows;
  std::uint64_t combined_mag = 0, combined_baro = 0;
};

Survey survey(const fs::path& file) {
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

/// A resolved field list of one subscription: `need` throws if absent (the source was chosen for it).
struct Fields {
  const Subscription& sub;
  const Field* opt(const std::string& name) const { return sub.field(name); }
  const Field& need(const std::string& name) const {
    const Field* f = sub.field(name);
    if (!f) throw std::out_of_range("topic '" + sub.name + "' has no field '" + name + "'");
    return *f;
  }
  std::array<const Field*, 3> vec(const std::string& name) const { return {&need(name + "[0]"), &need(name + "[1]"), &need(name + "[2]")}; }
  /// The first of `names` the format has, or nullptr.
  const Field* first_of(std::initializer_list<const char*> names) const {
    for (const char* n : names)
      if (const Field* f = sub.field(n)) return f;
    return nullptr;
  }
};

bool has_fields(const std::map<std::string, ulog::Format>& formats, const std::string& topic, std::initializer_list<const char*> names) {
  if (!formats.count(topic)) return false;
  const Subscription sub(topic, 0, 0, formats);
  for (const char* n : names)
    if (!sub.field(n)) return false;
  return true;
}

/// Everything the conversion pass carries.
class Conversion {
 public:
  Conversion(const ulog::Reader& reader, SensorLogWriter& out, ImportReport& report)
      : origin_us_(reader.start_timestamp()),
        params_(reader.initial_parameters()),
        report_(report),
        imu_(kWindow, [&out](const msg::Imu& m) { out.write("imu", m); }),
        mag_(kWindow, [&out](const msg::Mag& m) { out.write("mag", m); }),
        baro_(kWindow, [&out](const msg::Baro& m) { out.write("baro", m); }),
        dp_(kWindow, [&out](const msg::DiffPressure& m) { out.write("diff_pressure", m); }),
        gnss_(kWindow, [&out](const msg::Gnss& m) { out.write("gnss", m); }),
        ref_(kWindow, [&out](const msg::Reference& m) { out.write("reference", m); }) {}

  /// The handlers of one topic, built when its subscription (multi-instance 0) appears.
  using Handler = std::function<void(const DataMessage&)>;
  std::map<std::string, std::vector<std::function<Handler(const Fields&)>>> factories;
  std::map<std::uint16_t, std::vector<Handler>> handlers;

  void subscribe(const Subscription& s) {
    handlers.erase(s.msg_id);
    if (s.multi_id != 0) return;
    const auto it = factories.find(s.name);
    if (it == factories.end()) return;
    const Fields f{s};
    for (const auto& make : it->second) handlers[s.msg_id].push_back(make(f));
  }
  void data(const DataMessage& d) {
    const auto it = handlers.find(d.subscription().msg_id);
    if (it == handlers.end()) return;
    for (const auto& h : it->second) h(d);
  }

  /// us since boot -> the log's clock, ns; nullopt (counted) before the log's start.
  std::optional<Nanos> stamp(std::int64_t t_us) {
    if (t_us < static_cast<std::int64_t>(origin_us_)) {
      ++before_start_;
      return std::nullopt;
    }
    return (t_us - static_cast<std::int64_t>(origin_us_)) * 1000;
  }
  /// The sample's time: timestamp_sample if the format has it, else timestamp.
  std::optional<Nanos> sample_stamp(const DataMessage& d, const Field* timestamp_sample) {
    return stamp(timestamp_sample ? d.integer(*timestamp_sample) : static_cast<std::int64_t>(d.timestamp()));
  }
  std::optional<double> param(const std::string& name) const {
    const auto it = params_.find(name);
    if (it == params_.end()) return std::nullopt;
    return it->second.number();
  }

  // Each registers the handler factory of one output's source topic.
  void add_imu();
  void add_mag(const std::string& source);
  void add_baro(const std::string& source);
  void add_diff_pressure(const std::string& source);
  void add_gnss(const std::string& source);
  void add_attitude(const std::string& source);
  void add_position(const std::string& source);
  void add_velocity(const std::string& source);
  void add_wind(const std::string& source);
  /// Releases the rows still held and reports what was dropped.
  void finish(const std::string& file, std::vector<std::string>& notes);

  std::string date;  ///< of the first GNSS fix with a UTC time
  IntervalStats imu_intervals, gnss_intervals;

 private:
  void write_mag(Nanos t, double x, double y, double z);
  std::uint64_t origin_us_;
  const std::map<std::string, ulog::Value>& params_;
  ImportReport& report_;
  ReorderWindow<msg::Imu> imu_;
  ReorderWindow<msg::Mag> mag_;
  ReorderWindow<msg::Baro> baro_;
  ReorderWindow<msg::DiffPressure> dp_;
  ReorderWindow<msg::Gnss> gnss_;
  ReorderWindow<msg::Reference> ref_;
  std::uint64_t before_start_ = 0, nan_rows_ = 0, no_temperature_ = 0, course_velocity_ = 0;
  std::int64_t max_accel_relative_us_ = 0;
  Nanos last_combined_mag_ = -1, last_combined_baro_ = -1;
};

double temperature_k(double celsius, std::uint64_t& missing) {
  if (std::isfinite(celsius) && celsius > -100.0 && celsius < 150.0) return celsius + kCelsiusToKelvin;
  ++missing;
  return kNoTemperature;
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
      if (rel && d.integer(*rel) != kInvalidRelative) max_accel_relative_us_ = std::max(max_accel_relative_us_, std::abs(d.integer(*rel)));
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
        const auto t = stamp(static_cast<std::int64_t>(d.timestamp()) + r);
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
        t = stamp(static_cast<std::int64_t>(d.timestamp()) + r);
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
      m.temperature = temp ? temperature_k(d.value(*temp), no_temperature_) : (++no_temperature_, kNoTemperature);
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
      m.temperature = temp ? temperature_k(d.value(*temp), no_temperature_) : (++no_temperature_, kNoTemperature);
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
      if (ts)
        m.time_of_validity = std::max<Nanos>(0, (d.integer(*ts) - static_cast<std::int64_t>(origin_us_)) * 1000 - delay);  // 0: unknown
      if (!std::isfinite(m.lat) || !std::isfinite(m.lon) || !std::isfinite(m.alt) || !m.vel.allFinite() || !std::isfinite(m.h_acc) ||
          !std::isfinite(m.v_acc) || !std::isfinite(m.s_acc))
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

void Conversion::finish(const std::string& file, std::vector<std::string>& notes) {
  imu_.flush(), mag_.flush(), baro_.flush(), dp_.flush(), gnss_.flush(), ref_.flush();
  const std::uint64_t late = imu_.dropped() + mag_.dropped() + baro_.dropped() + dp_.dropped() + gnss_.dropped() + ref_.dropped();
  auto warn = [&](std::uint64_t n, const std::string& what) {
    if (n) report_.warnings.push_back(fmt::format("{}: {} {}", file, n, what));
  };
  warn(before_start_, "row(s) stamped before the log's start timestamp (stale samples published before logging began): dropped");
  warn(late, "row(s) more than 1 s out of time order within their topic: dropped");
  warn(nan_rows_, "sensor row(s) with a NaN or infinite value: dropped");
  warn(course_velocity_, "GNSS row(s) without a valid NED velocity (vel_ned_valid 0): north/east from vel_m_s and cog_rad");
  if (no_temperature_)
    notes.push_back(fmt::format("{} baro/diff_pressure rows without a usable temperature: 288.15 K written", no_temperature_));
  notes.push_back("imu temperature: not in sensor_combined; the message default 288.15 K is written");
  if (max_accel_relative_us_ > 0)
    notes.push_back(fmt::format("imu stamp: sensor_combined.timestamp (the gyro's); the accelerometer's differs by up to {} us",
                                max_accel_relative_us_));
}

/// An output's candidate source topics, best first, with the fields it needs.
struct Candidate {
  const char* topic;
  std::initializer_list<const char*> fields;
  std::uint64_t Survey::*samples = nullptr;  ///< a count of valid samples the survey must have found, if any
};

std::optional<std::string> choose(const Survey& s, const std::map<std::string, ulog::Format>& formats,
                                  std::initializer_list<Candidate> list) {
  for (const auto& c : list) {
    const auto it = s.rows.find(c.topic);
    if (it == s.rows.end() || it->second == 0 || !has_fields(formats, c.topic, c.fields)) continue;
    if (c.samples && s.*c.samples == 0) continue;
    return std::string(c.topic);
  }
  return std::nullopt;
}

/// Chooses each output's source, registers its handler, and notes the choice (or warns of its absence).
void choose_sources(const Survey& s, const ulog::Reader& r, Conversion& c, ImportReport& report, std::vector<std::string>& notes) {
  const auto& F = r.formats();
  const std::string file = r.path().string();
  auto pick = [&](const char* output, std::initializer_list<Candidate> list, const char* missing) -> std::optional<std::string> {
    auto src = choose(s, F, list);
    if (src)
      notes.push_back(fmt::format("{}: from {} ({} messages)", output, *src, s.rows.at(*src)));
    else
      report.warnings.push_back(fmt::format("{}: no {}: {}", file, output, missing));
    return src;
  };
  if (!pick("imu", {{"sensor_combined", {"gyro_rad[0]", "accelerometer_m_s2[0]"}}}, "the sensor log's imu topic is required"))
    throw ImportError(file + ": no sensor_combined data (gyro_rad, accelerometer_m_s2): a sensor log needs an imu topic");
  c.add_imu();
  if (auto src = pick("mag",
                      {{"vehicle_magnetometer", {"magnetometer_ga[0]"}},
                       {"sensor_combined", {"magnetometer_ga[0]", "magnetometer_timestamp_relative"}, &Survey::combined_mag},
                       {"sensor_mag", {"x", "y", "z"}}},
                      "vehicle_magnetometer, sensor_combined.magnetometer_ga or sensor_mag with data")) {
    c.add_mag(*src);
    if (*src == "sensor_mag")
      report.warnings.push_back(
          file + ": mag from raw sensor_mag instance 0: PX4's calibration (CAL_MAG*) is not applied, nor is the board rotation guaranteed");
  }
  if (auto src = pick("baro",
                      {{"vehicle_air_data", {"baro_alt_meter"}},
                       {"sensor_combined", {"baro_alt_meter", "baro_timestamp_relative"}, &Survey::combined_baro},
                       {"sensor_baro", {"pressure"}}},
                      "vehicle_air_data, sensor_combined.baro_alt_meter or sensor_baro with data"))
    c.add_baro(*src);
  if (auto src = pick("diff_pressure", {{"differential_pressure", {}}, {"airspeed", {"indicated_airspeed_m_s"}}},
                      "differential_pressure or airspeed with data")) {
    c.add_diff_pressure(*src);
    if (*src == "airspeed") notes.push_back("diff_pressure: airspeed.indicated_airspeed_m_s taken as EAS, 0.5 * 1.225 * EAS^2");
  }
  if (auto src = pick("gnss", {{"vehicle_gps_position", {"fix_type", "vel_n_m_s"}}, {"sensor_gps", {"fix_type", "vel_n_m_s"}}},
                      "vehicle_gps_position or sensor_gps with data (without GNSS the estimator never initialises)")) {
    c.add_gnss(*src);
    notes.push_back(
        "gnss: lat/lon/alt as logged (int32 1e-7 deg and mm, or doubles); h_acc/v_acc from eph/epv; s_acc from s_variance_m_s "
        "(the receiver's speed accuracy in m/s, 1 sigma, despite its name); fix_type 0-1 none, 2 2-D, 3-6 3-D, 7-8 dead reckoning");
  }
  if (auto src = pick("reference attitude", {{"vehicle_attitude", {"q[0]"}}, {"control_state", {"q[0]"}}},
                      "vehicle_attitude or control_state with data"))
    c.add_attitude(*src);
  if (auto src =
          pick("reference position",
               {{"vehicle_global_position", {"lat", "lon", "alt"}}, {"vehicle_local_position", {"ref_lat", "xy_global", "z_global"}}},
               "vehicle_global_position or vehicle_local_position with data"))
    c.add_position(*src);
  if (auto src = pick("reference velocity",
                      {{"vehicle_local_position", {"vx", "vy", "vz"}}, {"vehicle_global_position", {"vel_n", "vel_e", "vel_d"}}},
                      "vehicle_local_position or vehicle_global_position with data"))
    c.add_velocity(*src);
  if (auto src = pick("reference wind", {{"wind", {"windspeed_north"}}, {"wind_estimate", {"windspeed_north"}}},
                      "wind or wind_estimate with data"))
    c.add_wind(*src);
}

/// The PX4 parameters that map onto the estimator's settings (docs/sensor-log.md), where the log has them.
void estimator_settings(const Conversion& c, SensorLogMeta& meta) {
  auto delay = [&](const char* px4, const char* tern) {
    if (auto v = c.param(px4)) meta.estimator[tern] = *v * 1e-3;
  };
  delay("EKF2_GPS_DELAY", "gnss_delay");
  delay("EKF2_BARO_DELAY", "baro_delay");
  delay("EKF2_MAG_DELAY", "mag_delay");
  delay("EKF2_ASP_DELAY", "diff_pressure_delay");
  auto position = [&](const char* px4, const char* tern) {
    const auto x = c.param(fmt::format("{}_X", px4)), y = c.param(fmt::format("{}_Y", px4)), z = c.param(fmt::format("{}_Z", px4));
    if (x && y && z) meta.estimator[tern] = std::vector<double>{*x, *y, *z};
  };
  position("EKF2_GPS_POS", "gnss_antenna_position");
  position("EKF2_IMU_POS", "imu_position");
  meta.estimator["imu_mount"] = std::vector<double>{0.0, 0.0, 0.0};  // sensor_combined is already in the body frame
  auto& n = meta.notes;
  n.push_back(
      "estimator: gnss/baro/mag/diff_pressure delays from EKF2_GPS/BARO/MAG/ASP_DELAY (ms -> s), measured from each "
      "sample's timestamp_sample as PX4's EKF2 does; gnss_antenna_position from EKF2_GPS_POS_X/Y/Z, imu_position from EKF2_IMU_POS_X/Y/Z");
  std::string applied;
  for (const char* p :
       {"SENS_BOARD_ROT", "SENS_BOARD_X_OFF", "SENS_BOARD_Y_OFF", "SENS_BOARD_Z_OFF", "CAL_MAG0_XOFF", "CAL_MAG0_YOFF", "CAL_MAG0_ZOFF"})
    if (auto v = c.param(p)) applied += fmt::format(" {}={}", p, *v);
  n.push_back("imu_mount 0: PX4 applied the board rotation and calibration before sensor_combined/vehicle_magnetometer:" + applied);
  for (const char* p : {"EKF2_MAG_DECL", "EKF2_MAG_TYPE", "SENS_BARO_QNH"})
    if (auto v = c.param(p)) n.push_back(fmt::format("PX4 parameter {} = {} (not mapped)", p, *v));
}

std::string info_text(const ulog::Reader& r, const char* key) {
  const auto it = r.info().find(key);
  return it == r.info().end() ? std::string("?") : it->second.text();
}

ImportReport convert(const fs::path& ulg, SensorLogWriter& out) {
  const std::string file = ulg.string();
  const Survey s = survey(ulg);
  ulog::Reader r(ulg);
  ImportReport report;
  SensorLogMeta meta;
  Conversion c(r, out, report);
  choose_sources(s, r, c, report, meta.notes);
  std::uint64_t dropouts = 0, dropout_ms = 0;
  ulog::DataHandler h;
  h.on_subscription = [&](const Subscription& sub) { c.subscribe(sub); };
  h.on_data = [&](const DataMessage& d) { c.data(d); };
  h.on_dropout = [&](std::uint16_t ms, std::uint64_t) { ++dropouts, dropout_ms += ms; };
  const ulog::UlogDataStats stats = r.read_data(h);
  c.finish(file, meta.notes);
  for (auto& w : stats.warnings(file)) report.warnings.push_back(std::move(w));
  if (dropouts)
    report.warnings.push_back(
        fmt::format("{}: {} logging dropout(s), {} ms in all: data lost by PX4's logger", file, dropouts, dropout_ms));
  if (c.imu_intervals.count()) meta.notes.push_back("imu: " + c.imu_intervals.describe());
  if (c.gnss_intervals.count()) meta.notes.push_back("gnss: " + c.gnss_intervals.describe());
  meta.notes.push_back("times: PX4 timestamps (us since boot) minus the log's start timestamp " + std::to_string(r.start_timestamp()) +
                       " us");
  estimator_settings(c, meta);
  meta.source = fmt::format("PX4 ULog {} ({} {} on {}), by tern import ulog", ulg.filename().string(), info_text(r, "sys_name"),
                            info_text(r, "ver_sw"), info_text(r, "ver_hw"));
  meta.aircraft = fmt::format("PX4 MAV_TYPE {}, SYS_AUTOSTART {}", c.param("MAV_TYPE") ? fmt::format("{}", *c.param("MAV_TYPE")) : "?",
                              c.param("SYS_AUTOSTART") ? fmt::format("{}", *c.param("SYS_AUTOSTART")) : "?");
  meta.date = c.date;
  if (meta.date.empty())
    report.warnings.push_back(file + ": no GNSS fix with a UTC time: the flight's date is unknown (the magnetic model's date is not set)");
  out.finish(meta);
  report.rows = out.rows();
  return report;
}

}  // namespace

ImportReport import_ulog(const fs::path& in, SensorLogWriter& out) {
  std::error_code ec;
  fs::path ulg = in;
  if (fs::is_directory(in, ec)) {  // an unpacked archive: the one .ulg in it
    ulg = file_ending_with(in, ".ulg");
    if (ulg.empty()) throw ImportError(in.string() + ": no .ulg file in this directory");
  }
  try {
    return convert(ulg, out);
  } catch (const ulog::UlogError& e) {
    throw ImportError(e.what());
  } catch (const std::out_of_range& e) {
    throw ImportError(ulg.string() + ": " + e.what());
  }
}

}  // namespace tern::core
