// core/apps/import/dataflash_import.cpp: `tern import dataflash`: the survey, the handlers of each
// ArduPilot message, the servo outputs' mapping through the log's own parameters, sensor_log.yaml's
// settings and notes (the mapping: dataflash_import.hpp; the reader: dataflash_reader.hpp).
#include "import/dataflash_import.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "import/dataflash_reader.hpp"
#include "import/import_support.hpp"
#include "import/importers.hpp"
#include "import/ulog_import.hpp"
#include "tern/input_file.hpp"
#include "tern/math.hpp"
#include "tern/msg/control.hpp"
#include "tern/msg/estimator.hpp"

namespace tern::core {

namespace dataflash_import {

msg::FixType ardupilot_fix_type(int status) {
  if (status == 2) return msg::FixType::fix_2d;
  if (status >= 3 && status <= 6) return msg::FixType::fix_3d;
  return msg::FixType::none;
}

std::string iso_date_from_gps_week(std::int64_t week, std::int64_t week_ms) {
  constexpr std::int64_t kGpsEpochUnix = 315964800;  // 1980-01-06 00:00:00 UTC
  constexpr std::int64_t kLeapSeconds = 18;          // GPS - UTC since 2017-01-01
  if (week <= 0 || week > 100000 || week_ms < 0 || week_ms > 7 * 86400 * 1000) return "";
  const std::int64_t unix_s = kGpsEpochUnix + week * 7 * 86400 + week_ms / 1000 - kLeapSeconds;
  return ulog_import::iso_date_from_utc_usec(static_cast<std::uint64_t>(unix_s) * 1000000);
}

double angle_from_pwm(double pwm_us, const ServoRange& s) {
  const double v = pwm_us >= s.trim ? (s.max > s.trim ? (pwm_us - s.trim) / (s.max - s.trim) : 0.0)
                                    : (s.trim > s.min ? (pwm_us - s.trim) / (s.trim - s.min) : 0.0);
  return s.reversed ? 0.0 - v : v;
}

double range_from_pwm(double pwm_us, const ServoRange& s) {
  if (!(s.max > s.min)) return 0.0;
  const double v = std::clamp((pwm_us - s.min) / (s.max - s.min), 0.0, 1.0);
  return s.reversed ? 1.0 - v : v;
}

Unmixed unmix(double out1, double out2, double gain) { return {(out2 - out1) / (2.0 * gain), (out1 + out2) / (2.0 * gain)}; }

}  // namespace dataflash_import

namespace {

namespace fs = std::filesystem;
using namespace dataflash_import;
using dataflash::Field;
using dataflash::Format;
using dataflash::Message;
using ulog_import::ReorderWindow;

constexpr Nanos kReorderWindow = kNanosPerSecond;
constexpr double kMilligaussToTesla = 1e-7;
constexpr double kArspdRatioDefault = 1.9936;  // ArduPilot's ARSPD_RATIO default
constexpr int kRcouChannels = 14;              // RCOU's C1..C14 (15 and up are in RCO2, not read)
constexpr int kMaxServos = 32;
constexpr std::size_t kMaxParams = 1024;  // the parameters kept (those the mapping reads: SERVOn_*, ...)
constexpr std::size_t kMaxSidAxes = 64;

/// The messages converted; their TimeUS make the origin.
const std::set<std::string, std::less<>>& converted() {
  static const std::set<std::string, std::less<>> names = {"IMU", "GPS",  "GPA",  "BARO", "ARSP", "MAG",  "RCOU", "ATT",
                                                           "POS", "AHR2", "XKF1", "XKF2", "NKF1", "NKF2", "SIDD", "SIDS"};
  return names;
}

bool wanted_param(const std::string& name) {
  static const std::set<std::string, std::less<>> names = {
      "MIXING_GAIN", "MIXING_OFFSET", "ARSPD_RATIO", "GPS_DELAY_MS",  "GPS1_DELAY_MS", "EK3_HGT_DELAY", "AHRS_ORIENTATION",
      "GPS_POS1_X",  "GPS_POS1_Y",    "GPS_POS1_Z",  "GPS1_POS_X",    "GPS1_POS_Y",    "GPS1_POS_Z",    "INS_POS1_X",
      "INS_POS1_Y",  "INS_POS1_Z",    "SYSID_AXIS",  "AHRS_EKF_TYPE", "ARSPD_USE",     "ARSPD_TYPE",    "SYSID_MAGNITUDE"};
  return name.rfind("SERVO", 0) == 0 || names.count(name);
}

/// A reference value: an infinity (a corrupt float) as NaN, "not given" (the reference's columns may be NaN).
double finite_or_nan(double v) { return std::isfinite(v) ? v : std::numeric_limits<double>::quiet_NaN(); }

/// Whether m is instance 0 of its message (I, or C for the EKF's core; none: instance 0).
bool instance0(const Message& m) {
  const Field* i = m.format().field("I");
  if (!i) i = m.format().field("C");
  return !i || m.integer(*i) == 0;
}

/// Which messages hold data, the parameters, the origin.
struct Survey {
  std::map<std::string, std::uint64_t> rows;  ///< instance-0 messages by name (at most 256 names)
  std::optional<std::uint64_t> origin_us;
  std::map<std::string, double> params;  ///< the first value of each wanted parameter
  std::set<std::string> changed;         ///< wanted parameters whose value changed in the log
  std::uint64_t params_dropped = 0;
  std::string firmware;  ///< the first MSG naming ArduPilot's vehicle ("ArduPlane V4.5.1 (...)")
  std::set<int> sid_axes;
  bool gpa_vertical_velocity = false;
};

Survey survey(const fs::path& file) {
  dataflash::Reader r(file);
  Survey s;
  r.read([&](const Message& m) {
    const Format& f = m.format();
    if (f.name == "PARM") {
      const Field *name = f.field("Name"), *value = f.field("Value");
      if (!name || !value) return;
      const std::string n = m.text(*name);
      if (!wanted_param(n)) return;
      const double v = m.value(*value);
      const auto it = s.params.find(n);
      if (it == s.params.end()) {
        if (s.params.size() >= kMaxParams) return void(++s.params_dropped);
        s.params.emplace(n, v);
      } else if (it->second != v && s.changed.size() < kMaxParams) {
        s.changed.insert(n);
      }
      return;
    }
    if (f.name == "MSG" && s.firmware.empty()) {
      if (const Field* t = f.field("Message")) {
        const std::string text = m.text(*t);
        if (text.rfind("Ardu", 0) == 0) s.firmware = printable(text, 64);
      }
      return;
    }
    if (!converted().count(f.name) || !instance0(m)) return;
    ++s.rows[f.name];
    if (const auto t = m.time_us()) s.origin_us = std::min(s.origin_us.value_or(*t), *t);
    if (f.name == "SIDS" && s.sid_axes.size() < kMaxSidAxes)
      if (const Field* ax = f.field("Ax")) s.sid_axes.insert(static_cast<int>(m.integer(*ax)));
    if (f.name == "GPA")
      if (const Field* vv = f.field("VV"); vv && m.integer(*vv) != 0) s.gpa_vertical_velocity = true;
  });
  return s;
}

/// A message's fields, resolved once per format: `need` throws naming the message and label.
struct Fields {
  const Format& f;
  const Field* opt(const char* label) const { return f.field(label); }
  const Field& need(const char* label) const {
    const Field* x = f.field(label);
    if (!x)
      throw std::out_of_range("message '" + printable(f.name, 8) + "' (type " + std::to_string(f.type) + ") has no field '" + label + "'");
    return *x;
  }
};

/// The servo outputs' roles, from SERVOn_FUNCTION.
struct ServoMap {
  std::array<ServoRange, kMaxServos + 1> range;  ///< by 1-based channel
  std::vector<int> aileron, elevator, rudder, throttle;
  int elevon_left = 0, elevon_right = 0, vtail_left = 0, vtail_right = 0;  ///< 0: none
  double gain = 0.5;                                                       ///< MIXING_GAIN
  bool any_surface() const {
    return !aileron.empty() || !elevator.empty() || !rudder.empty() || (elevon_left && elevon_right) || (vtail_left && vtail_right);
  }
};

/// The normalised command of one RCOU message (nullopt: a mapped output is off, 0 us).
std::optional<NormalisedCommand> command_from_rcou(const std::array<double, kRcouChannels + 1>& pwm, const ServoMap& s) {
  auto on = [&](int ch) { return pwm[static_cast<std::size_t>(ch)] > 0.0; };
  auto angle = [&](int ch) { return angle_from_pwm(pwm[static_cast<std::size_t>(ch)], s.range[static_cast<std::size_t>(ch)]); };
  std::array<double, 3> sum{};
  std::array<int, 3> n{};
  auto add = [&](int axis, double v) { sum[static_cast<std::size_t>(axis)] += v, ++n[static_cast<std::size_t>(axis)]; };
  for (int ch : s.aileron)
    if (on(ch))
      add(0, angle(ch));
    else
      return std::nullopt;
  for (int ch : s.elevator)
    if (on(ch))
      add(1, angle(ch));
    else
      return std::nullopt;
  for (int ch : s.rudder)
    if (on(ch))
      add(2, angle(ch));
    else
      return std::nullopt;
  if (s.elevon_left && s.elevon_right) {
    if (!on(s.elevon_left) || !on(s.elevon_right)) return std::nullopt;
    const Unmixed u = unmix(angle(s.elevon_left), angle(s.elevon_right), s.gain);
    add(0, u.in1), add(1, u.in2);
  }
  if (s.vtail_left && s.vtail_right) {
    if (!on(s.vtail_left) || !on(s.vtail_right)) return std::nullopt;
    const Unmixed u = unmix(angle(s.vtail_right), angle(s.vtail_left), s.gain);
    add(2, u.in1), add(1, u.in2);
  }
  NormalisedCommand c;
  c.roll = n[0] ? sum[0] / n[0] : 0.0;
  c.pitch = n[1] ? sum[1] / n[1] : 0.0;
  c.yaw = n[2] ? sum[2] / n[2] : 0.0;
  double t = 0.0;
  for (int ch : s.throttle) t += range_from_pwm(pwm[static_cast<std::size_t>(ch)], s.range[static_cast<std::size_t>(ch)]);
  c.throttle = s.throttle.empty() ? 0.0 : t / static_cast<double>(s.throttle.size());
  return c;
}

class Conversion {
 public:
  Conversion(const Survey& s, SensorLogWriter& out)
      : survey_(s),
        origin_us_(s.origin_us.value_or(0)),
        imu_(kReorderWindow, [&out](const msg::Imu& m) { out.write("imu", m); }),
        mag_(kReorderWindow, [&out](const msg::Mag& m) { out.write("mag", m); }),
        baro_(kReorderWindow, [&out](const msg::Baro& m) { out.write("baro", m); }),
        dp_(kReorderWindow, [&out](const msg::DiffPressure& m) { out.write("diff_pressure", m); }),
        gnss_(kReorderWindow, [&out](const msg::Gnss& m) { out.write("gnss", m); }),
        ref_(kReorderWindow, [&out](const msg::Reference& m) { out.write("reference", m); }),
        act_(kReorderWindow, [&out](const msg::Actuators& m) { out.write("actuators", m); }),
        exc_(kReorderWindow, [&out](const msg::Actuators& m) { out.write("excitation", m); }) {}

  using Handler = std::function<void(const Message&)>;
  std::map<std::string, std::function<Handler(const Fields&)>, std::less<>> factories;

  void data(const Message& m) {
    const Format& f = m.format();
    if (bound_[f.type] != &f) {  // a type's first message: its handler, from its own FMT
      bound_[f.type] = &f;
      handlers_[f.type] = nullptr;
      if (const auto it = factories.find(f.name); it != factories.end()) handlers_[f.type] = it->second(Fields{f});
    }
    if (handlers_[f.type] && instance0(m)) handlers_[f.type](m);
  }

  /// TimeUS -> the log's clock, ns; nullopt (counted) without a TimeUS. Throws std::out_of_range for a
  /// time no int64 ns clock holds (import_dataflash names the file).
  std::optional<Nanos> stamp(const Message& m) {
    const auto t = m.time_us();
    if (!t || *t < origin_us_) return ++no_time_, std::nullopt;
    const std::uint64_t span = *t - origin_us_;
    if (span > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max() / 1000))
      throw std::out_of_range(
          fmt::format("byte {}: message '{}': field 'TimeUS': {} us is beyond any clock's range after the log's "
                      "first TimeUS ({} us): a corrupt file?",
                      m.offset(), printable(m.format().name, 8), *t, origin_us_));
    return static_cast<Nanos>(span) * 1000;
  }

  std::optional<double> param(const std::string& name) const {
    const auto it = survey_.params.find(name);
    return it == survey_.params.end() ? std::nullopt : std::optional<double>(it->second);
  }

  void add_imu() {
    factories["IMU"] = [this](const Fields& f) -> Handler {
      const std::array<const Field*, 6> v{&f.need("GyrX"), &f.need("GyrY"), &f.need("GyrZ"),
                                          &f.need("AccX"), &f.need("AccY"), &f.need("AccZ")};
      const Field* temp = f.opt("T");
      return [this, v, temp](const Message& m) {
        const auto t = stamp(m);
        if (!t) return;
        msg::Imu i;
        i.stamp = *t;
        for (int k = 0; k < 3; ++k)
          i.gyro[k] = m.value(*v[static_cast<std::size_t>(k)]), i.accel[k] = m.value(*v[static_cast<std::size_t>(k + 3)]);
        i.temperature = temperature_k(temp ? m.value(*temp) : std::nan(""));
        if (!i.gyro.allFinite() || !i.accel.allFinite()) return void(++nan_rows_);
        imu_intervals.add(i.stamp);
        imu_.push(i);
      };
    };
  }

  void add_mag() {
    factories["MAG"] = [this](const Fields& f) -> Handler {
      const std::array<const Field*, 3> v{&f.need("MagX"), &f.need("MagY"), &f.need("MagZ")};
      return [this, v](const Message& m) {
        const auto t = stamp(m);
        if (!t) return;
        msg::Mag g;
        g.stamp = *t;
        g.field = Eigen::Vector3d(m.value(*v[0]), m.value(*v[1]), m.value(*v[2])) * kMilligaussToTesla;
        if (!g.field.allFinite()) return void(++nan_rows_);
        mag_.push(g);
      };
    };
  }

  void add_baro() {
    factories["BARO"] = [this](const Fields& f) -> Handler {
      const Field *press = &f.need("Press"), *temp = f.opt("Temp");
      return [this, press, temp](const Message& m) {
        const auto t = stamp(m);
        if (!t) return;
        msg::Baro b;
        b.stamp = *t;
        b.pressure = m.value(*press);
        b.temperature = temperature_k(temp ? m.value(*temp) : std::nan(""));
        if (!std::isfinite(b.pressure)) return void(++nan_rows_);
        baro_.push(b);
      };
    };
  }

  void add_diff_pressure(double factor) {
    factories["ARSP"] = [this, factor](const Fields& f) -> Handler {
      const Field *dp = &f.need("DiffPress"), *temp = f.opt("Temp");
      return [this, dp, temp, factor](const Message& m) {
        const auto t = stamp(m);
        if (!t) return;
        msg::DiffPressure d;
        d.stamp = *t;
        d.pressure = m.value(*dp) * factor;
        d.temperature = temperature_k(temp ? m.value(*temp) : std::nan(""));
        if (!std::isfinite(d.pressure)) return void(++nan_rows_);
        dp_.push(d);
      };
    };
  }

  void add_gnss() {
    factories["GPS"] = [this](const Fields& f) -> Handler {
      const Field *status = &f.need("Status"), *lat = &f.need("Lat"), *lng = &f.need("Lng"), *alt = &f.need("Alt");
      const Field *spd = &f.need("Spd"), *crs = &f.need("GCrs"), *vz = f.opt("VZ"), *sats = f.opt("NSats"), *hdop = f.opt("HDop");
      const Field *week = f.opt("GWk"), *week_ms = f.opt("GMS");
      return [=, this](const Message& m) {
        const auto t = stamp(m);
        if (!t) return;
        flush_gnss();
        msg::Gnss g;
        g.stamp = *t;
        g.fix_type = ardupilot_fix_type(static_cast<int>(m.integer(*status)));
        g.num_sats = sats ? static_cast<std::uint8_t>(std::clamp<std::int64_t>(m.integer(*sats), 0, 255)) : 0;
        g.lat = m.value(*lat), g.lon = m.value(*lng), g.alt = m.value(*alt);
        const double speed = m.value(*spd), course = m.value(*crs) * kRadPerDeg;
        g.vel = {speed * std::cos(course), speed * std::sin(course), vz ? m.value(*vz) : 0.0};
        g.hdop = hdop ? m.value(*hdop) : 0.0;
        if (!std::isfinite(g.lat) || !std::isfinite(g.lon) || !std::isfinite(g.alt) || !g.vel.allFinite() || !std::isfinite(g.hdop))
          return void(++nan_rows_);
        if (date.empty() && week && week_ms && g.fix_type >= msg::FixType::fix_2d)
          date = iso_date_from_gps_week(m.integer(*week), m.integer(*week_ms));
        pending_gnss_ = g;
        pending_gnss_us_ = *m.time_us();
      };
    };
    factories["GPA"] = [this](const Fields& f) -> Handler {
      const Field *hacc = f.opt("HAcc"), *vacc = f.opt("VAcc"), *sacc = f.opt("SAcc"), *vdop = f.opt("VDop");
      return [=, this](const Message& m) {
        if (!pending_gnss_ || m.time_us() != pending_gnss_us_) return void(++unmatched_gpa_);
        auto val = [&](const Field* x) {
          const double v = x ? m.value(*x) : 0.0;
          return std::isfinite(v) && v >= 0.0 ? v : 0.0;
        };
        pending_gnss_->h_acc = val(hacc), pending_gnss_->v_acc = val(vacc), pending_gnss_->s_acc = val(sacc),
        pending_gnss_->vdop = val(vdop);
        ++gpa_rows_;
        flush_gnss();
      };
    };
  }

  void add_reference() {
    const bool att = survey_.rows.count("ATT"), pos = survey_.rows.count("POS"), ahr2 = survey_.rows.count("AHR2");
    const bool ahr2_att = !att && ahr2, ahr2_pos = !pos && ahr2;  // the backup DCM estimate where the primary is missing
    if (att) factories["ATT"] = [this](const Fields& f) -> Handler { return attitude(f); };
    if (pos) factories["POS"] = [this](const Fields& f) -> Handler { return position(f); };
    if (ahr2_att || ahr2_pos)
      factories["AHR2"] = [this, ahr2_att, ahr2_pos](const Fields& f) -> Handler {
        Handler a = ahr2_att ? attitude(f) : Handler(), p = ahr2_pos ? position(f) : Handler();
        return [a, p](const Message& m) {
          if (a) a(m);
          if (p) p(m);
        };
      };
    const char* vel = survey_.rows.count("XKF1") ? "XKF1" : survey_.rows.count("NKF1") ? "NKF1" : nullptr;
    if (vel)
      factories[vel] = [this](const Fields& f) -> Handler {
        const std::array<const Field*, 3> v{&f.need("VN"), &f.need("VE"), &f.need("VD")};
        return [this, v](const Message& m) {
          if (const auto t = stamp(m)) {
            msg::Reference r;
            r.stamp = *t;
            r.v_n = finite_or_nan(m.value(*v[0])), r.v_e = finite_or_nan(m.value(*v[1])), r.v_d = finite_or_nan(m.value(*v[2]));
            ref_.push(r);
          }
        };
      };
    const char* wind = survey_.rows.count("XKF2") ? "XKF2" : survey_.rows.count("NKF2") ? "NKF2" : nullptr;
    if (wind)
      factories[wind] = [this](const Fields& f) -> Handler {
        const Field *n = &f.need("VWN"), *e = &f.need("VWE");
        return [this, n, e](const Message& m) {
          if (const auto t = stamp(m)) {
            msg::Reference r;
            r.stamp = *t;
            r.w_n = finite_or_nan(m.value(*n)), r.w_e = finite_or_nan(m.value(*e));
            ref_.push(r);
          }
        };
      };
    reference_sources = std::string(att    ? "ATT"
                                    : ahr2 ? "AHR2"
                                           : "no") +
                        " attitude, " +
                        (pos    ? "POS"
                         : ahr2 ? "AHR2"
                                : "no") +
                        " position, " + (vel ? vel : "no") + " velocity, " + (wind ? wind : "no") + " wind";
  }

  void add_actuators(const ServoMap& map, const CommandMapping& mapping) {
    factories["RCOU"] = [this, map, mapping](const Fields& f) -> Handler {
      std::array<const Field*, kRcouChannels + 1> ch{};
      for (int i = 1; i <= kRcouChannels; ++i) ch[static_cast<std::size_t>(i)] = f.opt(fmt::format("C{}", i).c_str());
      auto used = map.aileron;
      used.insert(used.end(), map.elevator.begin(), map.elevator.end());
      used.insert(used.end(), map.rudder.begin(), map.rudder.end());
      used.insert(used.end(), map.throttle.begin(), map.throttle.end());
      for (int c : {map.elevon_left, map.elevon_right, map.vtail_left, map.vtail_right})
        if (c) used.push_back(c);
      for (int c : used)
        if (!ch[static_cast<std::size_t>(c)]) (void)f.need(fmt::format("C{}", c).c_str());  // throws naming it
      return [this, ch, map, mapping](const Message& m) {
        const auto t = stamp(m);
        if (!t) return;
        std::array<double, kRcouChannels + 1> pwm{};
        for (std::size_t i = 1; i < ch.size(); ++i) pwm[i] = ch[i] ? m.value(*ch[i]) : 0.0;
        const auto c = command_from_rcou(pwm, map);
        if (!c) return void(++outputs_off_);
        if (!std::isfinite(c->roll) || !std::isfinite(c->pitch) || !std::isfinite(c->yaw) || !std::isfinite(c->throttle))
          return void(++nan_rows_);
        const msg::Actuators a = actuators_from_normalised(*t, *c, mapping);
        actuator_intervals.add(a.stamp);
        act_.push(a);
      };
    };
  }

  /// SIDD's Targ as the excitation's part of the commands, on the axis of the SIDS before it.
  void add_excitation(const CommandMapping& mapping) {
    factories["SIDS"] = [this](const Fields& f) -> Handler {
      const Field* ax = &f.need("Ax");
      return [this, ax](const Message& m) {
        sid_axis_ = static_cast<int>(m.integer(*ax));
        end_excitation();
      };
    };
    factories["SIDD"] = [this, mapping](const Fields& f) -> Handler {
      const Field* targ = &f.need("Targ");
      return [this, targ, mapping](const Message& m) {
        const auto t = stamp(m);
        if (!t) return;
        const double u = m.value(*targ);
        if (!std::isfinite(u) || sid_axis_ < 10 || sid_axis_ > 13) return void(++excitation_dropped_);
        if (last_excitation_ && *t - *last_excitation_ > kNanosPerSecond / 2) end_excitation();
        if (excitation_rows == 0 && *t > 0) push_zero_excitation(0);  // 0 before the first manoeuvre
        NormalisedCommand c;
        (sid_axis_ == 10 ? c.roll : sid_axis_ == 11 ? c.pitch : sid_axis_ == 12 ? c.yaw : c.throttle) = u;
        const msg::Actuators a = actuators_from_normalised(*t, c, mapping);
        if (last_excitation_) excitation_interval_ = *t - *last_excitation_;
        last_excitation_ = *t;
        ++excitation_rows;
        exc_.push(a);
      };
    };
    excitation_mapping_ = mapping;
  }

  /// Releases the rows held and reports what was dropped.
  void finish(const std::string& file, ImportReport& report, std::vector<std::string>& notes) {
    flush_gnss();
    end_excitation();
    imu_.flush(), mag_.flush(), baro_.flush(), dp_.flush(), gnss_.flush(), ref_.flush(), act_.flush(), exc_.flush();
    const std::uint64_t late = imu_.dropped() + mag_.dropped() + baro_.dropped() + dp_.dropped() + gnss_.dropped() + ref_.dropped() +
                               act_.dropped() + exc_.dropped();
    auto warn = [&](std::uint64_t n, const std::string& what) {
      if (n) report.warnings.push_back(fmt::format("{}: {} {}", file, n, what));
    };
    warn(no_time_, "message(s) without a TimeUS field: dropped");
    warn(late, "row(s) more than 1 s out of time order within their topic: dropped");
    warn(nan_rows_, "sensor row(s) with a NaN or infinite value: dropped");
    warn(outputs_off_, "RCOU row(s) with a mapped output off (0 us: disarmed, or SERVOn_FUNCTION's output disabled): dropped");
    warn(unmatched_gpa_, "GPA message(s) without a GPS message of the same TimeUS before them: their accuracies are not used");
    warn(excitation_dropped_, "SIDD row(s) outside a mixer-axis manoeuvre (SIDS Ax 10-13) or NaN: dropped");
    if (no_temperature_)
      notes.push_back(fmt::format("{} imu/baro/diff_pressure rows without a usable temperature: {:.2f} K written", no_temperature_,
                                  msg::Baro{}.temperature));
    if (gpa_rows_) notes.push_back(fmt::format("gnss: h_acc, v_acc, s_acc, vdop from GPA ({} of the GPS rows)", gpa_rows_));
  }

  std::string date;
  std::string reference_sources;
  IntervalStats imu_intervals, actuator_intervals;
  std::uint64_t excitation_rows = 0;

 private:
  double temperature_k(double celsius) { return kelvin_from_celsius(celsius, no_temperature_); }
  void flush_gnss() {
    if (pending_gnss_) gnss_.push(*pending_gnss_);
    pending_gnss_.reset();
  }
  void push_zero_excitation(Nanos t) {
    msg::Actuators z;
    z.stamp = t + from_seconds(excitation_mapping_.command_delay);
    exc_.push(z);
  }
  /// The manoeuvre ended: a zero row one sample after its last.
  void end_excitation() {
    if (!last_excitation_) return;
    push_zero_excitation(*last_excitation_ + (excitation_interval_ > 0 ? excitation_interval_ : kNanosPerSecond / 50));
    last_excitation_.reset();
    excitation_interval_ = 0;
  }
  Handler attitude(const Fields& f) {
    const Field *roll = &f.need("Roll"), *pitch = &f.need("Pitch"), *yaw = &f.need("Yaw");
    return [this, roll, pitch, yaw](const Message& m) {
      const auto t = stamp(m);
      if (!t) return;
      msg::Reference r;
      r.stamp = *t;
      r.phi = finite_or_nan(m.value(*roll) * kRadPerDeg), r.theta = finite_or_nan(m.value(*pitch) * kRadPerDeg);
      r.psi = finite_or_nan(std::remainder(m.value(*yaw) * kRadPerDeg, 2.0 * kPi));  // ArduPilot's 0..360 deg as (-pi, pi]
      if (r.psi <= -kPi) r.psi += 2.0 * kPi;
      ref_.push(r);
    };
  }
  Handler position(const Fields& f) {
    const Field *lat = &f.need("Lat"), *lng = &f.need("Lng"), *alt = &f.need("Alt");
    return [this, lat, lng, alt](const Message& m) {
      const auto t = stamp(m);
      if (!t) return;
      msg::Reference r;
      r.stamp = *t;
      r.lat = finite_or_nan(m.value(*lat)), r.lon = finite_or_nan(m.value(*lng)), r.alt = finite_or_nan(m.value(*alt));
      ref_.push(r);
    };
  }

  const Survey& survey_;
  std::uint64_t origin_us_;
  std::array<const Format*, 256> bound_{};
  std::array<Handler, 256> handlers_;
  ReorderWindow<msg::Imu> imu_;
  ReorderWindow<msg::Mag> mag_;
  ReorderWindow<msg::Baro> baro_;
  ReorderWindow<msg::DiffPressure> dp_;
  ReorderWindow<msg::Gnss> gnss_;
  ReorderWindow<msg::Reference> ref_;
  ReorderWindow<msg::Actuators> act_;
  ReorderWindow<msg::Actuators> exc_;
  std::optional<msg::Gnss> pending_gnss_;
  std::uint64_t pending_gnss_us_ = 0;
  int sid_axis_ = 0;
  std::optional<Nanos> last_excitation_;
  Nanos excitation_interval_ = 0;
  CommandMapping excitation_mapping_;
  std::uint64_t no_time_ = 0, nan_rows_ = 0, no_temperature_ = 0, outputs_off_ = 0, unmatched_gpa_ = 0, gpa_rows_ = 0,
                excitation_dropped_ = 0;
};

/// SERVOn_FUNCTION and its range parameters as the outputs' roles; "" or the reason none can be used.
std::string servo_map(const Conversion& c, ServoMap& map, std::vector<std::string>& roles) {
  std::string unread;
  for (int ch = 1; ch <= kMaxServos; ++ch) {
    const auto fn = c.param(fmt::format("SERVO{}_FUNCTION", ch));
    if (!fn || !(*fn >= 0.0 && *fn <= 255.0)) continue;  // ArduPilot's functions are 0..~200 (NaN: none)
    const int function = static_cast<int>(*fn);
    const char* role = function == 4    ? "aileron"
                       : function == 19 ? "elevator"
                       : function == 21 ? "rudder"
                       : function == 70 ? "throttle"
                       : function == 77 ? "elevon left"
                       : function == 78 ? "elevon right"
                       : function == 79 ? "V-tail left"
                       : function == 80 ? "V-tail right"
                                        : nullptr;
    if (!role) continue;
    if (ch > kRcouChannels) {
      unread += fmt::format("{}SERVO{}_FUNCTION {} ({})", unread.empty() ? "" : ", ", ch, function, role);
      continue;
    }
    auto& r = map.range[static_cast<std::size_t>(ch)];
    r.min = c.param(fmt::format("SERVO{}_MIN", ch)).value_or(r.min);
    r.trim = c.param(fmt::format("SERVO{}_TRIM", ch)).value_or(r.trim);
    r.max = c.param(fmt::format("SERVO{}_MAX", ch)).value_or(r.max);
    r.reversed = c.param(fmt::format("SERVO{}_REVERSED", ch)).value_or(0.0) != 0.0;
    if (!(std::isfinite(r.min) && std::isfinite(r.max) && r.min < r.max && r.trim >= r.min && r.trim <= r.max))
      return fmt::format("SERVO{}_MIN {} TRIM {} MAX {} for its {}: not MIN <= TRIM <= MAX", ch, r.min, r.trim, r.max, role);
    roles.push_back(fmt::format("C{} {} (SERVO{}_FUNCTION {}, MIN {} TRIM {} MAX {}{})", ch, role, ch, function, r.min, r.trim, r.max,
                                r.reversed ? ", REVERSED" : ""));
    switch (function) {
      case 4: map.aileron.push_back(ch); break;
      case 19: map.elevator.push_back(ch); break;
      case 21: map.rudder.push_back(ch); break;
      case 70: map.throttle.push_back(ch); break;
      case 77: map.elevon_left = map.elevon_left ? -1 : ch; break;
      case 78: map.elevon_right = map.elevon_right ? -1 : ch; break;
      case 79: map.vtail_left = map.vtail_left ? -1 : ch; break;
      case 80: map.vtail_right = map.vtail_right ? -1 : ch; break;
      default: break;
    }
  }
  if (!unread.empty()) return unread + ": beyond RCOU's C1..C14 (RCO2 is not read)";
  for (int x : {map.elevon_left, map.elevon_right, map.vtail_left, map.vtail_right})
    if (x < 0) return "two servo outputs of the same elevon or V-tail side: not a simple mixer";
  if ((map.elevon_left != 0) != (map.elevon_right != 0)) return "an elevon on one side only (SERVOn_FUNCTION 77 or 78)";
  if ((map.vtail_left != 0) != (map.vtail_right != 0)) return "a V-tail surface on one side only (SERVOn_FUNCTION 79 or 80)";
  if (map.elevon_left || map.vtail_left) {
    map.gain = c.param("MIXING_GAIN").value_or(0.5);
    if (!(map.gain > 0.0 && map.gain <= 10.0)) return fmt::format("MIXING_GAIN {}: not a mixer gain", map.gain);
    if (const auto off = c.param("MIXING_OFFSET"); off && *off != 0.0)
      return fmt::format("MIXING_OFFSET {} (a differential elevon/V-tail mix): not undone", *off);
  }
  if (!map.any_surface()) return "no SERVOn_FUNCTION of a surface (4 aileron, 19 elevator, 21 rudder, 77/78 elevons, 79/80 V-tail)";
  return "";
}

void choose_actuators(const Survey& s, const fs::path& bin, Conversion& c, const CommandMapping& mapping, ImportReport& report,
                      std::vector<std::string>& notes) {
  const std::string file = bin.string();
  if (!s.rows.count("RCOU")) {
    report.warnings.push_back(file +
                              ": no surface commands in this log (no RCOU messages): no actuators.csv written (tern sysid needs one)");
    return;
  }
  ServoMap map;
  std::vector<std::string> roles;
  if (const std::string why = servo_map(c, map, roles); !why.empty()) {
    report.warnings.push_back(
        fmt::format("{}: RCOU holds the servo outputs, but the log's parameters say {}: no actuators.csv written; the "
                    "sensors are imported",
                    file, why));
    return;
  }
  if (!mapping.max_deflection) {
    report.warnings.push_back(fmt::format(
        "{}: RCOU holds the surfaces' commands as servo pulses: no actuators.csv written without --max-deflection A E R (rad: the full "
        "aileron, elevator and rudder deflections, the aircraft file's servos.max_delta_a/e/r; a DataFlash log does not hold them)",
        file));
    return;
  }
  c.add_actuators(map, mapping);
  std::string joined;
  for (const auto& r : roles) joined += (joined.empty() ? "" : "; ") + r;
  notes.push_back(fmt::format("actuators: from RCOU ({} messages) through the log's parameters: {}", s.rows.at("RCOU"), joined));
  notes.push_back(
      "actuators: each surface's pulse as ArduPilot's scaled output, (pwm - TRIM) / (MAX - TRIM) above the trim and / (TRIM - MIN) "
      "below, negated when REVERSED; two surfaces of one axis averaged; elevons and V-tails unmixed as ArduPlane mixes them "
      "(MIXING_GAIN " +
      fmt::format("{}", map.gain) + "); throttle (pwm - MIN) / (MAX - MIN), 0..1; an axis without a surface 0");
  for (const auto& p : s.changed)
    if (p.rfind("SERVO", 0) == 0 || p.rfind("MIXING", 0) == 0)
      report.warnings.push_back(fmt::format("{}: parameter {} changes during the log: the mapping uses its first value", file, p));
  notes.push_back(describe(mapping));
  if (s.rows.count("SIDD")) {
    bool mixer = !s.sid_axes.empty();
    std::string axes;
    for (int a : s.sid_axes) {
      axes += fmt::format("{}{}", axes.empty() ? "" : ", ", a);
      mixer = mixer && a >= 10 && a <= 13;
    }
    if (!mixer) {
      report.warnings.push_back(fmt::format(
          "{}: SIDD holds a system-identification manoeuvre on SIDS axis {} (not all Mixer Roll/Pitch/Yaw/Thrust, 10-13: an angle or "
          "rate target, not a surface command): no excitation.csv written",
          file, axes.empty() ? std::string("unknown (no SIDS)") : axes));
    } else {
      c.add_excitation(mapping);
      notes.push_back("excitation: SIDD Targ (a fraction of the full command on SIDS axis " + axes +
                      ": 10 roll, 11 pitch, 12 yaw, 13 throttle) through the same deflections and signs; 0 before, between and after "
                      "the manoeuvres");
    }
  }
}

/// ArduPilot's parameters that map onto the estimator's settings, where the log has them.
void estimator_settings(const Survey& s, const Conversion& c, SensorLogMeta& meta) {
  auto& n = meta.notes;
  const auto gps_delay = c.param("GPS1_DELAY_MS") ? c.param("GPS1_DELAY_MS") : c.param("GPS_DELAY_MS");
  if (gps_delay && *gps_delay > 0.0) {
    meta.estimator["gnss_delay"] = *gps_delay * 1e-3;
    n.push_back(fmt::format("estimator: gnss_delay from GPS_DELAY_MS/GPS1_DELAY_MS {} ms", *gps_delay));
  } else {
    n.push_back("estimator: GPS_DELAY_MS 0 or absent (ArduPilot then uses its driver's lag): gnss_delay left at the estimator's default");
  }
  if (const auto h = c.param("EK3_HGT_DELAY"); h && *h >= 0.0) {
    meta.estimator["baro_delay"] = *h * 1e-3;
    n.push_back(fmt::format("estimator: baro_delay from EK3_HGT_DELAY {} ms", *h));
  }
  auto position = [&](const char* a, const char* b, const char* tern) {
    for (const char* p : {a, b}) {
      const auto x = c.param(fmt::format("{}_X", p)), y = c.param(fmt::format("{}_Y", p)), z = c.param(fmt::format("{}_Z", p));
      if (x && y && z) return void(meta.estimator[tern] = std::vector<double>{*x, *y, *z});
    }
  };
  position("GPS1_POS", "GPS_POS1", "gnss_antenna_position");
  position("INS_POS1", "INS_POS1", "imu_position");
  meta.estimator["imu_mount"] = std::vector<double>{0.0, 0.0, 0.0};  // IMU is logged in the body frame
  n.push_back(fmt::format("imu_mount 0: ArduPilot applied AHRS_ORIENTATION ({}) and the calibration before IMU and MAG",
                          c.param("AHRS_ORIENTATION") ? fmt::format("{}", *c.param("AHRS_ORIENTATION")) : "?"));
  if (s.rows.count("GPA") && !s.gpa_vertical_velocity) {
    meta.estimator["use_gnss_vel_d"] = false;
    n.push_back("gnss: GPA's VV is 0 throughout (the receiver gives no vertical velocity): vel_d 0, use_gnss_vel_d false");
  }
}

ImportReport convert(const fs::path& bin, SensorLogWriter& out, const CommandMapping& mapping) {
  const std::string file = bin.string();
  const Survey s = survey(bin);
  ImportReport report;
  SensorLogMeta meta;
  if (!s.rows.count("IMU")) throw ImportError(file + ": no IMU messages (GyrX, AccX, ... of instance 0): a sensor log needs an imu topic");
  Conversion c(s, out);
  auto& notes = meta.notes;
  auto source = [&](const char* output, const char* message, const char* missing) {
    if (s.rows.count(message)) {
      notes.push_back(fmt::format("{}: from {} ({} messages of instance 0)", output, message, s.rows.at(message)));
      return true;
    }
    report.warnings.push_back(fmt::format("{}: no {}: {}", file, output, missing));
    return false;
  };
  source("imu", "IMU", "");
  c.add_imu();
  notes.push_back(
      "imu: IMU holds ArduPilot's filtered samples (INS_GYRO_FILTER, INS_ACCEL_FILTER and any notch), one per main loop: not the "
      "sensor's raw rate");
  if (source("mag", "MAG", "no MAG messages")) c.add_mag();
  if (source("baro", "BARO", "no BARO messages")) c.add_baro();
  if (source("diff_pressure", "ARSP", "no ARSP messages (no airspeed sensor)")) {
    const auto ratio = c.param("ARSPD_RATIO");
    const double r = ratio && *ratio > 0.0 ? *ratio : kArspdRatioDefault;
    c.add_diff_pressure(r * kIsaSeaLevelDensity / 2.0);
    notes.push_back(fmt::format(
        "diff_pressure: ARSP DiffPress * ARSPD_RATIO ({}{}) * {} / 2, so that the estimator's EAS sqrt(2 p / {}) is ArduPilot's "
        "Airspeed sqrt(DiffPress * ARSPD_RATIO)",
        r, ratio ? "" : ", ArduPilot's default: not in the log", kIsaSeaLevelDensity, kIsaSeaLevelDensity));
  }
  if (source("gnss", "GPS", "no GPS messages (without GNSS the estimator never initialises)")) {
    c.add_gnss();
    notes.push_back(
        "gnss: Lat/Lng/Alt as logged (deg, m MSL); vel_n/vel_e from Spd and GCrs, vel_d VZ; fix_type from Status (0-1 none, 2 2-D, 3-6 "
        "3-D); hdop HDop; time_of_validity 0 (the log holds the time ArduPilot processed the fix)");
  }
  c.add_reference();
  notes.push_back("reference: " + c.reference_sources);
  choose_actuators(s, bin, c, mapping, report, notes);
  dataflash::Reader r(bin);
  const dataflash::DataflashStats stats = r.read([&](const Message& m) { c.data(m); });
  c.finish(file, report, notes);
  for (auto& w : stats.warnings(file)) report.warnings.push_back(std::move(w));
  if (s.params_dropped)
    report.warnings.push_back(fmt::format("{}: {} parameters beyond the first {} kept: ignored", file, s.params_dropped, kMaxParams));
  if (c.imu_intervals.count()) notes.push_back("imu: " + c.imu_intervals.describe());
  if (c.actuator_intervals.count()) {
    notes.push_back("actuators: " + c.actuator_intervals.describe());
    if (c.actuator_intervals.count() > 1)
      if (auto w = actuator_rate_warning(file, 1.0 / c.actuator_intervals.mean_s()); !w.empty()) report.warnings.push_back(w);
  }
  notes.push_back(fmt::format("times: ArduPilot's TimeUS (us since boot) minus the log's first {} us", s.origin_us.value_or(0)));
  estimator_settings(s, c, meta);
  meta.source = fmt::format("ArduPilot DataFlash {} ({}), by tern import dataflash", bin.filename().string(),
                            s.firmware.empty() ? std::string("no firmware message") : s.firmware);
  meta.aircraft = s.firmware.empty() ? std::string("ArduPilot vehicle") : s.firmware;
  meta.date = c.date;
  if (meta.date.empty())
    report.warnings.push_back(file + ": no GPS fix with a GPS week: the flight's date is unknown (the magnetic model's date is not set)");
  if (!s.firmware.empty() && s.firmware.rfind("ArduPlane", 0) != 0)
    report.warnings.push_back(
        fmt::format("{}: the firmware is '{}', not ArduPlane: its servo outputs may not be a fixed wing's surfaces", file, s.firmware));
  out.finish(meta, report.warnings);
  report.rows = out.rows();
  return report;
}

}  // namespace

ImportReport import_dataflash(const fs::path& in, SensorLogWriter& out, const CommandMapping& commands) {
  std::error_code ec;
  fs::path bin = in;
  if (fs::is_directory(in, ec)) {  // an unpacked archive: the one .bin (or .BIN) in it
    bin = file_ending_with(in, ".bin");
    if (bin.empty()) bin = file_ending_with(in, ".BIN");
    if (bin.empty()) throw ImportError(in.string() + ": no .bin file in this directory");
  }
  try {
    return convert(bin, out, commands);
  } catch (const dataflash::DataflashError& e) {
    throw ImportError(e.what());
  } catch (const std::out_of_range& e) {  // a field a message lacks, a time beyond any clock: one line
    throw ImportError(bin.string() + ": " + printable(e.what(), 1000));
  }
}

}  // namespace tern::core
