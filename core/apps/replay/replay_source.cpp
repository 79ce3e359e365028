#include "replay/replay_source.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <spdlog/logger.h>

#include "config/error.hpp"
#include "replay/replay_csv.hpp"
#include "replay/sensor_units.hpp"
#include "replay/table_limits.hpp"
#include "tern/input_file.hpp"

namespace tern::core {

namespace {

/// One cell into the message field at `dst`; false if it is not a number. An empty cell or "nan"
/// is NaN (a reference that lacks a field).
template <class V>
bool store(char* dst, const std::string& text) {
  V v{};
  if constexpr (std::is_floating_point_v<V>) {
    if (text.empty()) {
      v = std::numeric_limits<V>::quiet_NaN();
    } else {
      char* end = nullptr;
      v = static_cast<V>(std::strtod(text.c_str(), &end));
      if (end == text.c_str() || *end != '\0') return false;
    }
  } else {
    long long x = 0;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
    if (ec != std::errc() || ptr != text.data() + text.size()) return false;
    v = static_cast<V>(x);
  }
  std::memcpy(dst, &v, sizeof v);
  return true;
}

bool store_cell(const reflect::Column& c, char* p, const std::string& cell) {
  switch (c.kind) {
    case reflect::Scalar::f64: return store<double>(p, cell);
    case reflect::Scalar::f32: return store<float>(p, cell);
    case reflect::Scalar::i64: return store<std::int64_t>(p, cell);
    case reflect::Scalar::i32: return store<std::int32_t>(p, cell);
    case reflect::Scalar::i16: return store<std::int16_t>(p, cell);
    case reflect::Scalar::i8: return store<std::int8_t>(p, cell);
    case reflect::Scalar::u64: return store<std::uint64_t>(p, cell);
    case reflect::Scalar::u32: return store<std::uint32_t>(p, cell);
    case reflect::Scalar::u16: return store<std::uint16_t>(p, cell);
    case reflect::Scalar::u8: return store<std::uint8_t>(p, cell);
    case reflect::Scalar::boolean: return store<std::uint8_t>(p, cell);
  }
  return false;
}

/// A line of a table written with Windows' line ends (CRLF: a spreadsheet's export), without its '\r'.
void drop_carriage_return(std::string& line) {
  if (!line.empty() && line.back() == '\r') line.pop_back();
}

/// The header's columns mapped onto T's layout by name; a unit in brackets other than the
/// layout's is an error (docs/sensor-log.md), and so is a column the topic requires missing
/// (table_limits.hpp). Column 0 is `t [s]`.
std::vector<const reflect::Column*> map_columns(const std::filesystem::path& csv, const std::string& topic, const std::string& header,
                                                const std::vector<reflect::Column>& layout) {
  std::vector<const reflect::Column*> cols;
  std::string item;
  for (std::stringstream h(header); std::getline(h, item, ',');) {
    const auto bracket = item.find(" [");
    const std::string name = item.substr(0, bracket);
    const reflect::Column* col = nullptr;
    for (const auto& c : layout)
      if (c.name == name) col = &c;
    if (col && bracket != std::string::npos) {
      const std::string unit = item.substr(bracket + 2, item.size() - bracket - 3);
      if (unit != col->unit)
        throw ConfigError(fmt::format("{}:1: column {} '{}': unit '{}', expected '{}' (docs/sensor-log.md)", csv.string(), cols.size() + 1,
                                      name, unit, col->unit));
    }
    if (col != nullptr && !cols.empty() && std::find(cols.begin(), cols.end(), col) != cols.end())
      throw ConfigError(fmt::format("{}:1: column '{}' twice in the header (docs/sensor-log.md)", csv.string(), name));
    cols.push_back(cols.empty() ? nullptr : col);
  }
  if (cols.empty() || header.rfind("t [s]", 0) != 0)
    throw ConfigError(csv.string() + ":1: the first column must be 't [s]' (docs/sensor-log.md)");
  for (const std::string& name : required_columns(topic))
    if (std::none_of(cols.begin(), cols.end(), [&](const reflect::Column* c) { return c != nullptr && c->name == name; }))
      throw ConfigError(fmt::format("{}:1: no column '{}': the {} table needs it (docs/sensor-log.md)", csv.string(), name, topic));
  return cols;
}

/// What a table held that replay did not play: rows dropped, cells that were NaN.
struct TableProblems {
  std::size_t backwards = 0, nan_rows = 0;
  std::size_t first_backwards_line = 0, first_nan_line = 0;
};

/// The table's values against their units where a wrong unit would have every sample refused
/// (sensor_units.hpp): the IMU's, GNSS's, barometer's, pitot's and magnetometer's; the others as read.
template <class T>
void require_units(const std::filesystem::path&, const std::vector<std::pair<Nanos, T>>&) {}
void require_units(const std::filesystem::path& csv, const std::vector<std::pair<Nanos, msg::Imu>>& rows) {
  std::vector<double> f, w;
  f.reserve(rows.size()), w.reserve(rows.size());
  for (const auto& [t, m] : rows) f.push_back(m.accel.norm()), w.push_back(m.gyro.norm());
  require_imu_magnitudes(csv, std::move(f), w);
}
void require_units(const std::filesystem::path& csv, const std::vector<std::pair<Nanos, msg::Baro>>& rows) {
  std::vector<double> p;
  p.reserve(rows.size());
  for (const auto& [t, m] : rows) p.push_back(m.pressure);
  require_pressure_unit(csv, std::move(p));
}
void require_units(const std::filesystem::path& csv, const std::vector<std::pair<Nanos, msg::Mag>>& rows) {
  std::vector<double> b;
  b.reserve(rows.size());
  for (const auto& [t, m] : rows) b.push_back(m.field.norm());
  require_field_unit(csv, std::move(b));
}
void require_units(const std::filesystem::path& csv, const std::vector<std::pair<Nanos, msg::Gnss>>& rows) {
  GnssFixes f;
  for (const auto& [t, m] : rows) {
    if (m.fix_type != msg::FixType::fix_2d && m.fix_type != msg::FixType::fix_3d) continue;
    f.lat.push_back(m.lat), f.lon.push_back(m.lon), f.alt.push_back(m.alt), f.speed.push_back(m.vel.norm());
  }
  require_gnss_units(csv, std::move(f));
}
void require_units(const std::filesystem::path& csv, const std::vector<std::pair<Nanos, msg::DiffPressure>>& rows) {
  std::vector<double> p;
  p.reserve(rows.size());
  for (const auto& [t, m] : rows) p.push_back(m.pressure);
  require_pitot_sign(csv, std::move(p));
}

template <class T>
class Track final : public ReplaySource::TrackBase {
 public:
  /// `nan_expected`: a table whose NaN cells mean "not given" (reference), not worth a warning.
  Track(const std::filesystem::path& csv, const std::string& topic, bool nan_expected) : out_(std::make_unique<Output<T>>()) {
    check_table_file(csv);
    std::ifstream in(csv);
    std::string header;
    std::getline(in, header);
    drop_byte_order_mark(header);
    drop_carriage_return(header);
    require_comma_separated(csv, header);
    const auto layout = reflect::layout<T>();
    const auto cols = map_columns(csv, topic, header, layout);
    std::string line, cell;
    std::size_t lineno = 1;
    while (std::getline(in, line)) {
      ++lineno;
      drop_carriage_return(line);
      if (line.empty()) continue;
      if (in.eof()) {  // no line end: the flight was cut off while writing this row
        partial_ = fmt::format(
            "{}:{}: the last line is partial ({} characters, no line end: the flight was cut off "
            "while writing it): dropped",
            csv.string(), lineno, line.size());
        break;
      }
      read_row(csv, line, lineno, cols, nan_expected);
    }
    require_units(csv, rows_);
    if (p_.backwards)
      warnings_.push_back(fmt::format("{}: {} rows whose time goes backwards dropped (first at line {})", csv.string(), p_.backwards,
                                      p_.first_backwards_line));
    if (p_.nan_rows)
      warnings_.push_back(fmt::format("{}: {} rows with NaN values (first at line {}): played, the estimator rejects them", csv.string(),
                                      p_.nan_rows, p_.first_nan_line));
  }
  void publish_until(Nanos now) override {
    while (next_ < rows_.size() && rows_[next_].first <= now) out_->publish(rows_[next_++].second);
  }
  void rewind() override { next_ = 0; }
  Nanos last_time() const override { return rows_.empty() ? 0 : rows_.back().first; }
  std::size_t rows() const override { return rows_.size(); }
  std::size_t played() const override { return next_; }
  const std::string& partial_last_line() const override { return partial_; }
  const std::vector<std::string>& warnings() const override { return warnings_; }
  Output<T>& output() { return *out_; }

 private:
  void read_row(const std::filesystem::path& csv, const std::string& line, std::size_t lineno,
                const std::vector<const reflect::Column*>& cols, bool nan_expected) {
    T msg{};
    Nanos t = 0;
    std::size_t i = 0;
    bool nan = false;
    std::string cell;
    for (std::stringstream ls(line); std::getline(ls, cell, ','); ++i) {
      if (i == 0) {
        const std::optional<Nanos> parsed = parse_log_time(cell);
        if (!parsed)
          throw ConfigError(fmt::format("{}:{}: t [s] '{}' is not a decimal number of seconds within {} s of the log's origin{}",
                                        csv.string(), lineno, printable(cell), kMaxLogTime,
                                        unix_time_hint(std::strtod(cell.c_str(), nullptr))));
        t = *parsed;
        continue;
      }
      if (i >= cols.size() || cols[i] == nullptr) continue;
      if (!store_cell(*cols[i], reinterpret_cast<char*>(&msg) + cols[i]->offset, cell))
        throw ConfigError(fmt::format("{}:{}: column {} '{}': '{}' is not a number", csv.string(), lineno, i + 1, cols[i]->name, cell));
      if (cols[i]->kind == reflect::Scalar::f64 &&
          !std::isfinite(*reinterpret_cast<double*>(reinterpret_cast<char*>(&msg) + cols[i]->offset)))
        nan = true;
    }
    if (!line.empty() && line.back() == ',') ++i;  // a last empty cell
    if (i != cols.size())
      throw ConfigError(csv.string() + ":" + std::to_string(lineno) + ": expected " + std::to_string(cols.size()) + " values, got " +
                        std::to_string(i) + (i < cols.size() ? " (a truncated log?)" : " (more cells than the header names)"));
    t_check_.check(csv, lineno, t);
    if constexpr (std::is_same_v<decltype(msg.stamp), Nanos>) {
      stamp_check_.check(csv, lineno, msg.stamp);
      check_stamp_at_t(csv, lineno, t, msg.stamp);
    }
    if (!rows_.empty() && t < rows_.back().first) {
      if (p_.backwards++ == 0) p_.first_backwards_line = lineno;
      return;
    }
    if (nan && !nan_expected && p_.nan_rows++ == 0) p_.first_nan_line = lineno;
    rows_.emplace_back(t, msg);
  }

  std::unique_ptr<Output<T>> out_;
  std::vector<std::pair<Nanos, T>> rows_;
  std::size_t next_ = 0;
  std::string partial_;
  std::vector<std::string> warnings_;
  TableProblems p_;
  RowTimes t_check_{"t"}, stamp_check_{"stamp"};
};

}  // namespace

ReplaySource::ReplaySource(std::filesystem::path run_dir, bool comparisons) : dir_(std::move(run_dir)), comparisons_(comparisons) {}
ReplaySource::~ReplaySource() = default;

void ReplaySource::configure() {
  if (!std::filesystem::is_directory(dir_ / "topics"))
    throw ConfigError("replay: '" + dir_.string() + "' is not a flight log directory (no topics/)");
  auto add = [&](auto tag, const std::string& topic, bool feedback = false) {
    using T = decltype(tag);
    const auto csv = dir_ / "topics" / (topic + ".csv");
    if (!std::filesystem::exists(csv)) return;
    auto track = std::make_unique<Track<T>>(csv, topic, topic == "reference");
    if (!track->partial_last_line().empty()) log().warn("{}", track->partial_last_line());
    for (const auto& w : track->warnings()) log().warn("{}", w);
    track->feedback = feedback;
    track->topic = topic;
    this->declare(track->output(), topic, "recorded " + topic);
    tracks_.push_back(std::move(track));
  };
  add(msg::Imu{}, "imu");
  add(msg::Gnss{}, "gnss");
  add(msg::Baro{}, "baro");
  add(msg::DiffPressure{}, "diff_pressure");
  add(msg::Mag{}, "mag");
  add(msg::Actuators{}, "actuators", true);
  if (comparisons_) {
    add(msg::State{}, "truth");
    add(msg::Reference{}, "reference");
  }
  if (!std::filesystem::exists(dir_ / "topics" / "imu.csv"))
    throw ConfigError("replay: '" + dir_.string() + "' has no topics/imu.csv to replay");
  if (tracks_.front()->rows() == 0)
    throw ConfigError((dir_ / "topics" / "imu.csv").string() + ": the IMU table has no rows: nothing to replay");
  end_ = tracks_.front()->last_time();
}

void ReplaySource::start() {
  for (auto& t : tracks_) t->rewind();
}

std::vector<std::pair<std::string, double>> ReplaySource::summary() const {
  std::vector<std::pair<std::string, double>> s;
  for (const auto& t : tracks_) {
    s.emplace_back(t->topic + "_rows", static_cast<double>(t->rows()));
    s.emplace_back(t->topic + "_played", static_cast<double>(t->played()));
  }
  return s;
}

void ReplaySource::step(Nanos now) {
  for (auto& t : tracks_) t->publish_until(t->feedback ? now - 1 : now);
}

RecordedSourceFactory replay_source(std::filesystem::path run_dir, bool comparisons) {
  return [run_dir = std::move(run_dir), comparisons] { return std::make_unique<ReplaySource>(run_dir, comparisons); };
}

}  // namespace tern::core
