#include "replay/replay_source.hpp"

#include <charconv>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <spdlog/logger.h>

#include "config/error.hpp"

namespace tern::core {

namespace {

/// "12.345000000" -> 12345000000 ns, exactly.
Nanos parse_time(const std::string& s) {
  const auto dot = s.find('.');
  long long sec = 0, frac = 0;
  std::from_chars(s.data(), s.data() + (dot == std::string::npos ? s.size() : dot), sec);
  if (dot != std::string::npos) {
    std::string f = s.substr(dot + 1);
    f.resize(9, '0');
    std::from_chars(f.data(), f.data() + 9, frac);
  }
  return sec * 1'000'000'000LL + (s.rfind('-', 0) == 0 ? -frac : frac);
}

template <class V>
void store(char* dst, const std::string& text) {
  V v{};
  if constexpr (std::is_floating_point_v<V>) {
    v = static_cast<V>(std::strtod(text.c_str(), nullptr));
  } else {
    long long x = 0;
    std::from_chars(text.data(), text.data() + text.size(), x);
    v = static_cast<V>(x);
  }
  std::memcpy(dst, &v, sizeof v);
}

template <class T>
class Track final : public ReplaySource::TrackBase {
 public:
  explicit Track(const std::filesystem::path& csv) : out_(std::make_unique<Output<T>>()) {
    std::ifstream in(csv);
    std::string header;
    std::getline(in, header);
    std::vector<std::string> names;
    for (std::stringstream h(header); std::getline(h, header, ',');) names.push_back(header.substr(0, header.find(" [")));
    const auto layout = reflect::layout<T>();
    std::vector<const reflect::Column*> cols(names.size(), nullptr);
    for (std::size_t i = 1; i < names.size(); ++i)
      for (const auto& c : layout)
        if (c.name == names[i]) cols[i] = &c;
    std::string line, cell;
    std::size_t lineno = 1;
    while (std::getline(in, line)) {
      ++lineno;
      if (line.empty()) continue;
      if (in.eof()) {  // no line end: the flight was cut off while writing this row
        partial_ = fmt::format(
            "{}:{}: the last line is partial ({} characters, no line end: the flight was cut off "
            "while writing it): dropped",
            csv.string(), lineno, line.size());
        break;
      }
      T msg{};
      Nanos t = 0;
      std::size_t i = 0;
      for (std::stringstream ls(line); std::getline(ls, cell, ','); ++i) {
        if (i == 0) {
          t = parse_time(cell);
          continue;
        }
        if (i >= cols.size() || cols[i] == nullptr) continue;
        char* p = reinterpret_cast<char*>(&msg) + cols[i]->offset;
        switch (cols[i]->kind) {
          case reflect::Scalar::f64: store<double>(p, cell); break;
          case reflect::Scalar::f32: store<float>(p, cell); break;
          case reflect::Scalar::i64: store<std::int64_t>(p, cell); break;
          case reflect::Scalar::i32: store<std::int32_t>(p, cell); break;
          case reflect::Scalar::i16: store<std::int16_t>(p, cell); break;
          case reflect::Scalar::i8: store<std::int8_t>(p, cell); break;
          case reflect::Scalar::u64: store<std::uint64_t>(p, cell); break;
          case reflect::Scalar::u32: store<std::uint32_t>(p, cell); break;
          case reflect::Scalar::u16: store<std::uint16_t>(p, cell); break;
          case reflect::Scalar::u8: store<std::uint8_t>(p, cell); break;
          case reflect::Scalar::boolean: store<std::uint8_t>(p, cell); break;
        }
      }
      if (i != names.size())
        throw ConfigError(csv.string() + ":" + std::to_string(lineno) + ": expected " + std::to_string(names.size()) + " values, got " +
                          std::to_string(i) + " (a truncated log?)");
      rows_.emplace_back(t, msg);
    }
  }
  void publish_until(Nanos now) override {
    while (next_ < rows_.size() && rows_[next_].first <= now) out_->publish(rows_[next_++].second);
  }
  void rewind() override { next_ = 0; }
  Nanos last_time() const override { return rows_.empty() ? 0 : rows_.back().first; }
  const std::string& partial_last_line() const override { return partial_; }
  Output<T>& output() { return *out_; }

 private:
  std::unique_ptr<Output<T>> out_;
  std::vector<std::pair<Nanos, T>> rows_;
  std::size_t next_ = 0;
  std::string partial_;
};

}  // namespace

ReplaySource::ReplaySource(std::filesystem::path run_dir) : dir_(std::move(run_dir)) {}
ReplaySource::~ReplaySource() = default;

void ReplaySource::configure() {
  if (!std::filesystem::is_directory(dir_ / "topics"))
    throw ConfigError("replay: '" + dir_.string() + "' is not a flight log directory (no topics/)");
  auto add = [&](auto tag, const std::string& topic, bool feedback = false) {
    using T = decltype(tag);
    const auto csv = dir_ / "topics" / (topic + ".csv");
    if (!std::filesystem::exists(csv)) return;
    auto track = std::make_unique<Track<T>>(csv);
    if (!track->partial_last_line().empty()) log().warn("replay: {}", track->partial_last_line());
    track->feedback = feedback;
    this->declare(track->output(), topic, "recorded " + topic);
    tracks_.push_back(std::move(track));
  };
  add(msg::Imu{}, "imu");
  add(msg::Gnss{}, "gnss");
  add(msg::Baro{}, "baro");
  add(msg::DiffPressure{}, "diff_pressure");
  add(msg::Mag{}, "mag");
  add(msg::Actuators{}, "actuators", true);
  add(msg::State{}, "truth");
  if (!std::filesystem::exists(dir_ / "topics" / "imu.csv"))
    throw ConfigError("replay: '" + dir_.string() + "' has no topics/imu.csv to replay");
  end_ = tracks_.front()->last_time();
}

void ReplaySource::start() {
  for (auto& t : tracks_) t->rewind();
}

void ReplaySource::step(Nanos now) {
  for (auto& t : tracks_) t->publish_until(t->feedback ? now - 1 : now);
}

}  // namespace tern::core
