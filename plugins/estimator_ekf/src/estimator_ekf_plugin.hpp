// estimator_ekf plugin class (header so that tests can instantiate it): binds tern::ekf::Estimator to ports and parameters.
//
// Inputs: imu (required), gnss, baro, diff_pressure, mag, actuators (optional). The sensors'
// inputs are queues (kSensorQueue messages, tern/port.hpp): every sample published since the
// previous step reaches the filter, oldest first, each with its own stamp (a replay plays several
// rows of one topic inside one 2.5-ms step); the IMU's first, then gnss, baro, diff_pressure, mag.
// A sample the queue could not hold is counted (summary.json `<input>_missed`, only when some
// were) and warned about once. actuators: the latest command only.
// Outputs: state (msg::State), every output_decimation-th IMU sample, and on every step while the
// IMU is silent (status invalid); innovations (msg::Innovations) every innovations_period.
// Schedule it with `rate:` at the IMU's rate rather than `trigger: imu`: only a plugin stepped
// by the clock notices that the IMU went silent.
// Every figure of EstimatorConfig a mission may set is a parameter, named in
// EstimatorConfig::describe (estimator_config.hpp) next to its default; changes apply from the next step.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "tern/aircraft.hpp"
#include "tern/estimator_ekf/estimator.hpp"
#include "tern/math.hpp"
#include "tern/plugin.hpp"

namespace tern::ekf::plugin {

using tern::ekf::EstimatorConfig;

/// What the plugin adds to the filter's parameters: how often it publishes.
struct OutputConfig {
  std::int64_t decimation = 1;      ///< publish state every n-th IMU sample
  double innovations_period = 0.1;  ///< s

  template <class V>
  static void describe(V& v) {
    using tern::ParamSpec;
    v(&OutputConfig::decimation, "output_decimation", ParamSpec("", 1, 1000, "publish state every n-th IMU sample"));
    v(&OutputConfig::innovations_period, "innovations_period", ParamSpec("s", 0.0025, 10.0, "period of the innovations output"));
  }
};

/// Samples of one sensor an input holds between two steps: 25 ms of a 1-kHz IMU at a 400-Hz step.
inline constexpr std::uint32_t kSensorQueue = 64;

class EstimatorEkf final : public tern::Plugin {
 public:
  void configure() override {
    using tern::Need;
    const tern::Queue q{kSensorQueue};
    declare(imu_, "imu", "IMU samples; each one propagates the filter (use trigger: imu)", Need::required, q);
    declare(gnss_, "gnss", "GNSS solutions: origin, position and velocity updates", Need::optional, q);
    declare(baro_, "baro", "static pressure: altitude updates after the ground calibration", Need::optional, q);
    declare(diff_, "diff_pressure", "pitot differential pressure: airspeed and zero-sideslip updates", Need::optional, q);
    declare(mag_, "mag", "magnetometer: attitude (heading) updates", Need::optional, q);
    declare(actuators_, "actuators", "surface deflections for the side- and normal-force models (delta_a, delta_e, delta_r)",
            Need::optional);
    declare(state_, "state", "the estimate; status: ok, degraded (which sensor) or invalid");
    declare(innovations_, "innovations", "largest innovation test ratio (NIS / gate) of each measurement over innovations_period");

    // Defaults from the mission's aircraft file when it has them: the air density
    // (environment: rho:, so that the pitot model matches the simulator's; else ROSplane's
    // 1.225 kg/m^3) and, for the side-force model, mass, wing area and the C_Y derivatives.
    if (!context().describing() && !context().aircraft_file().empty()) read_aircraft(context().aircraft_file().string(), config_);
    // The fixed Earth's field is an override: a mission that sets any of it means it (the default
    // of mag_field_from_model becomes false, as the aircraft file's figures become defaults).
    if (context().configured_value("mag_declination", tern::ParamSpec()) ||
        context().configured_value("mag_inclination", tern::ParamSpec()) ||
        context().configured_value("mag_field_strength", tern::ParamSpec()))
      config_.mag_field_from_model = false;
    // Every figure of EstimatorConfig a mission may set, by the names of EstimatorConfig::describe.
    declare_struct(config_, [this] { dirty_ = true; });
    declare_struct(output_);
    estimator_.set_config(config_);
  }

  void start() override {
    estimator_.set_config(config_);
    estimator_.expect_mag(mag_.connected());
    // A wired sensor silent from the start times out, unless a replayed log's clock starts
    // anywhere (Context::replaying()): then each sensor's time-out starts at its first sample.
    const bool live = !context().replaying();
    estimator_.expect(Sensor::imu, live);
    estimator_.expect(Sensor::gnss, gnss_.connected() && live);
    estimator_.expect(Sensor::baro, baro_.connected() && live);
    estimator_.expect(Sensor::diff_pressure, diff_.connected() && live);
    estimator_.expect(Sensor::mag, mag_.connected() && live);
  }

  void step(tern::Nanos now) override {
    if (dirty_) {
      estimator_.set_config(config_);
      dirty_ = false;
    }
    const bool imu_new = imu_.updated();
    take_samples();
    if (actuators_.updated()) estimator_.set_controls(actuators_->delta_a, actuators_->delta_e, actuators_->delta_r);
    // On the host's clock: with `rate:` scheduling a silent IMU times out here.
    estimator_.check_timeouts(now);
    if (estimator_.has_events()) {
      for (const auto& e : estimator_.take_events()) {
        if (e.kind == tern::ekf::EventKind::sensor_timeout || e.kind == tern::ekf::EventKind::gnss_reset ||
            e.kind == tern::ekf::EventKind::filter_reset || e.kind == tern::ekf::EventKind::mag_reset ||
            e.kind == tern::ekf::EventKind::first_invalid || e.kind == tern::ekf::EventKind::imu_gap ||
            e.kind == tern::ekf::EventKind::gnss_yaw_reset || e.kind == tern::ekf::EventKind::gnss_velocity_reset ||
            e.kind == tern::ekf::EventKind::gsf_yaw_reset || e.kind == tern::ekf::EventKind::launch_yaw_alignment)
          log().warn("t={:.3f} s: {}", tern::to_seconds(e.stamp), tern::ekf::describe(e));
        else if (e.kind == tern::ekf::EventKind::gnss_checks_failing && e.value != 0.0)  // with the values and limits
          log().info("t={:.3f} s: {} ({})", tern::to_seconds(e.stamp), tern::ekf::describe(e), estimator_.gnss_checks().describe_failing());
        else
          log().info("t={:.3f} s: {}", tern::to_seconds(e.stamp), tern::ekf::describe(e));
        if (e.kind == tern::ekf::EventKind::origin_set) log_earth_field(e.stamp);
      }
    }
    const bool imu_silent = estimator_.counters(tern::ekf::Sensor::imu).timed_out;
    if ((imu_new || imu_silent) && (flight_.ticks++ % output_.decimation) == 0) {
      estimator_.fill_state(out_);
      if (imu_silent) out_.stamp = now;  // the invalid state is news of now
      state_.publish(out_);
    }
    if (now - flight_.last_innovations >= tern::from_seconds(output_.innovations_period)) {
      innovations_.publish(estimator_.take_innovations(now));
      flight_.last_innovations = now;
    }
  }

  /// A new flight: the estimator as new (same configuration and wiring) and the plugin's own
  /// per-flight state replaced wholesale; parameters are kept.
  void reset() override {
    estimator_.reset();
    flight_ = Flight{};
  }

  std::vector<std::pair<std::string, double>> summary() const override {
    using tern::ekf::Sensor;
    std::vector<std::pair<std::string, double>> s;
    for (int i = 0; i < tern::ekf::kSensorCount; ++i) {
      const auto sensor = static_cast<Sensor>(i);
      const auto& c = estimator_.counters(sensor);
      const std::string n = tern::ekf::sensor_name(sensor);
      s.emplace_back(n + "_received", static_cast<double>(c.received));
      s.emplace_back(n + "_invalid", static_cast<double>(c.invalid));
      s.emplace_back(n + "_timeouts", static_cast<double>(c.timeouts));
    }
    for (std::size_t i = 0; i < flight_.missed.size(); ++i)
      if (flight_.missed[i] > 0)
        s.emplace_back(std::string(sensor_inputs()[i]->name()) + "_missed", static_cast<double>(flight_.missed[i]));
    for (const auto& [name, st] : update_stats()) {
      s.emplace_back(name + "_accepted", static_cast<double>(st->accepted));
      s.emplace_back(name + "_rejected", static_cast<double>(st->rejected));
      if (st->nis_count > 0) s.emplace_back(name + "_mean_nis", st->mean_nis());
    }
    s.emplace_back("gnss_resets", static_cast<double>(estimator_.gnss_resets()));
    s.emplace_back("mag_resets", static_cast<double>(estimator_.mag_resets()));
    // of gnss_resets (each resets the position too), not a reset of its own: no "_resets" suffix
    s.emplace_back("gnss_yaw_reset_count", static_cast<double>(estimator_.gnss_yaw_resets()));
    s.emplace_back("mag_resumes", static_cast<double>(estimator_.mag_resumes()));
    s.emplace_back("filter_resets", static_cast<double>(estimator_.filter_resets()));
    s.emplace_back("inflations", static_cast<double>(estimator_.inflations()));
    s.emplace_back("gnss_constellation_jumps", static_cast<double>(estimator_.constellation_jumps()));
    // the largest variance factor of each robustly fused sensor's inflations (0: never)
    s.emplace_back("gnss_inflation_max", estimator_.inflation_max(Sensor::gnss));
    s.emplace_back("baro_inflation_max", estimator_.inflation_max(Sensor::baro));
    // The GNSS start-up checks: the wait from the first fix to the one that passed (s), when one did.
    const auto& checks = estimator_.gnss_checks();
    if (checks.passed()) s.emplace_back("gnss_checks_wait", tern::to_seconds(checks.passed_stamp() - checks.first_stamp()));
    return s;
  }

  /// "N resets, M inflations" and each measurement with rejections: "baro 0.9 % rejected".
  std::string health() const override {
    std::string s = fmt::format("{} resets (gnss {}, mag {}, filter {}), {} inflations",
                                estimator_.gnss_resets() + estimator_.mag_resets() + estimator_.filter_resets(), estimator_.gnss_resets(),
                                estimator_.mag_resets(), estimator_.filter_resets(), estimator_.inflations());
    for (const auto& [name, st] : update_stats())
      if (st->rejected > 0)
        s += fmt::format(", {} {:.1f} % rejected", name,
                         100.0 * static_cast<double>(st->rejected) / static_cast<double>(st->accepted + st->rejected));
    for (int i = 0; i < tern::ekf::kSensorCount; ++i) {
      const auto& c = estimator_.counters(static_cast<tern::ekf::Sensor>(i));
      if (c.timeouts > 0) s += fmt::format(", {} timed out {}x", tern::ekf::sensor_name(static_cast<tern::ekf::Sensor>(i)), c.timeouts);
    }
    return s;
  }

  /// Each measurement model's name (its summary.json prefix) and its counts this flight.
  std::vector<std::pair<std::string, const tern::ekf::UpdateStats*>> update_stats() const {
    const tern::ekf::Estimator& e = estimator_;
    return {{"gnss_pos", &e.gnss_position_model().stats},
            {"gnss_vel", &e.gnss_velocity_stats()},
            {"mag", &e.mag_model().stats},
            {"mag_heading", &e.mag_heading_model().stats},
            {"baro", &e.baro_model().stats},
            {"diff_pressure", &e.diff_pressure_model().stats},
            {"sideslip", &e.sideslip_model().stats},
            {"side_force", &e.side_force_model().stats},
            {"normal_force", &e.normal_force_model().stats}};
  }

  /// For tests in the same process: the estimator behind the ports.
  const tern::ekf::Estimator& estimator() const { return estimator_; }

 private:
  /// Every sample the sensors' queues received since the previous step into the filter, in
  /// order; the ones a queue could not hold counted and warned about once per input.
  void take_samples() {
    for (const auto& m : imu_.received()) estimator_.add_imu(m);
    for (const auto& m : gnss_.received()) estimator_.add_gnss(m);
    for (const auto& m : baro_.received()) estimator_.add_baro(m);
    for (const auto& m : diff_.received()) estimator_.add_diff_pressure(m);
    for (const auto& m : mag_.received()) estimator_.add_mag(m);
    const auto inputs = sensor_inputs();
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      const std::uint64_t n = inputs[i]->missed();
      if (n > 0 && flight_.missed[i] == 0)
        log().warn("{}: {} samples between two steps did not fit the input's queue ({}): lost (further losses counted in summary.json)",
                   inputs[i]->name(), n, inputs[i]->queue_depth());
      flight_.missed[i] += n;
    }
  }
  /// The sensors' inputs, in the order their samples are taken.
  std::array<const tern::InputBase*, 5> sensor_inputs() const { return {&imu_, &gnss_, &baro_, &diff_, &mag_}; }

  /// The Earth's field the magnetometer is compared with, once the origin is known.
  void log_earth_field(tern::Nanos stamp) {
    const tern::MagneticField& f = estimator_.earth_field();
    const auto line = fmt::format("t={:.3f} s: Earth's field ({} on {:.2f}): declination {:.2f} deg, inclination {:.2f} deg, {:.1f} uT",
                                  tern::to_seconds(stamp), f.model, config_.mag_model_date, f.declination * tern::kDegPerRad,
                                  f.inclination * tern::kDegPerRad, f.intensity * 1e6);
    if (f.extrapolated)
      log().warn("{} (the date is outside the model's 5 years: extrapolated)", line);
    else
      log().info("{}", line);
  }

  /// Takes what the estimator can use from the aircraft file (tern or ROSflight format, read and
  /// validated by tern/aircraft.hpp): air density, mass, wing area and chord, the side-force
  /// (C_Y_*) and lift (C_L_*) coefficients. Throws std::runtime_error naming the file, the field
  /// and the value (a missing required field, a non-finite or implausible number).
  static void read_aircraft(const std::string& path, EstimatorConfig& c) {
    const tern::Aircraft ac = tern::load_aircraft(path);
    c.rho = ac.rho;
    c.mass = ac.mass;
    c.wing_S = ac.S;
    c.wing_c = ac.c;
    c.C_Y_0 = ac.aero.C_Y_0;
    c.C_Y_beta = ac.aero.C_Y_beta;
    c.C_Y_delta_a = ac.aero.C_Y_delta_a;
    c.C_Y_delta_r = ac.aero.C_Y_delta_r;
    c.C_L_0 = ac.aero.C_L_0;
    c.C_L_alpha = ac.aero.C_L_alpha;
    c.C_L_q = ac.aero.C_L_q;
    c.C_L_delta_e = ac.aero.C_L_delta_e;
  }

  tern::Input<tern::msg::Imu> imu_;
  tern::Input<tern::msg::Gnss> gnss_;
  tern::Input<tern::msg::Baro> baro_;
  tern::Input<tern::msg::DiffPressure> diff_;
  tern::Input<tern::msg::Mag> mag_;
  tern::Input<tern::msg::Actuators> actuators_;
  tern::Output<tern::msg::State> state_;
  tern::Output<tern::msg::Innovations> innovations_;
  EstimatorConfig config_;  ///< the parameters' values (EstimatorConfig::describe)
  OutputConfig output_;
  tern::ekf::Estimator estimator_;
  tern::msg::State out_;  ///< scratch: the estimate is filled in place before it is published
  /// Everything one flight changes (besides the estimator): reset() replaces it wholesale.
  struct Flight {
    std::uint64_t ticks = 0;                ///< IMU samples seen (output decimation)
    std::array<std::uint64_t, 5> missed{};  ///< per sensor_inputs(): samples their queues could not hold
    tern::Nanos last_innovations = std::numeric_limits<tern::Nanos>::min() / 2;
  } flight_;
  bool dirty_ = false;
};

}  // namespace tern::ekf::plugin
