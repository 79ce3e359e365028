// core/host/record/metrics.hpp: the flight's figures of merit, as in the ROSplane 2.0 paper.
//
// A built-in instance named `metrics`, present when some plugin publishes `state`. It steps on
// every `state` update (sampled at most every `period` s of flight time) and accumulates, over
// the window that starts when the first loop of the mission is complete (or at `start_after` s
// when the mission has no loops) and only while the flight phase is cruise:
//  - estimation RMSE, estimate vs truth (needs `truth`): north, east, altitude (m), roll, pitch,
//    heading (deg), course (deg), airspeed (m/s), wind north/east (m/s); positions compared in the
//    truth's frame (common_frame.hpp: the estimator's origin mapped to the simulator's);
//  - the raw-GNSS baseline (needs `truth` and `gnss`): the latest fix at each sample against
//    the truth at that sample, north, east, altitude (m), in the same frame;
//  - tracking RMSE, command vs estimate: north and east distance from the estimated position to
//    the closest point of the commanded path segment (line or orbit, horizontal), altitude
//    h_c - h, roll phi_c - phi, pitch theta_c - theta, course chi_c - chi (wrapped), airspeed
//    Va_c - Va; and the largest cross-track and altitude errors.
// It also records every waypoint passage (current_path.waypoint_index changes) and counts loops,
// and, with `truth` and a land item, the touchdown (landing_report.hpp).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "record/landing_report.hpp"
#include "tern/plugin.hpp"

namespace tern::core {

class FlightMetrics final : public Plugin {
 public:
  struct Rms {
    double sum_sq = 0;
    std::uint64_t n = 0;
    void add(double e) {
      if (std::isfinite(e)) {
        sum_sq += e * e;
        ++n;
      }
    }
    double value() const { return n ? std::sqrt(sum_sq / static_cast<double>(n)) : std::nan(""); }
  };
  struct Passage {
    Nanos t;
    int index;
  };
  enum Est { e_north, e_east, e_alt, e_roll, e_pitch, e_heading, e_course, e_airspeed, e_wind_n, e_wind_e, kEst };
  enum Trk { t_north, t_east, t_alt, t_roll, t_pitch, t_course, t_airspeed, kTrk };
  static constexpr std::array<const char*, kEst> kEstNames = {"north_m",        "east_m",       "altitude_m", "roll_deg",
                                                              "pitch_deg",      "heading_deg",  "course_deg", "airspeed_mps",
                                                              "wind_north_mps", "wind_east_mps"};
  static constexpr int kGnss = 3;  ///< north, east, altitude (the first three of kEstNames)
  static constexpr std::array<const char*, kTrk> kTrkNames = {"north_m",   "east_m",     "altitude_m",  "roll_deg",
                                                              "pitch_deg", "course_deg", "airspeed_mps"};

  void configure() override;
  void start() override { reset(); }
  void reset() override;
  void step(Nanos now) override;
  std::vector<std::pair<std::string, double>> summary() const override;

  const std::array<Rms, kEst>& estimation() const { return f_.est; }
  const std::array<Rms, kTrk>& tracking() const { return f_.trk; }
  const std::array<Rms, kGnss>& raw_gnss() const { return f_.gnss_err; }
  bool has_gnss() const { return gnss_.connected(); }
  const std::vector<Passage>& passages() const { return f_.passages; }
  int loops() const { return f_.loops; }
  double max_cross_track() const { return f_.max_cross; }   ///< m, horizontal, over the window
  double max_altitude_error() const { return f_.max_alt; }  ///< m, |h_c - h| over the window
  bool has_truth() const { return truth_.connected(); }
  Nanos window_start() const { return f_.window_start; }
  const std::optional<Touchdown>& touchdown() const { return f_.landing.touchdown(); }

 private:
  void add_estimation_errors(const msg::State& estimate, const msg::State& truth);

  Input<msg::State> state_, truth_;
  Input<msg::Gnss> gnss_;
  Input<msg::ControllerCommand> command_;
  Input<msg::ControllerInternals> internals_;
  Input<msg::CurrentPath> path_;
  Input<msg::FlightPhase> phase_;
  Input<msg::WaypointList> waypoints_;
  Param<double> period_, start_after_;
  Param<bool> cruise_only_;
  /// Everything one flight changes: reset() replaces it wholesale.
  struct Flight {
    std::array<Rms, kEst> est{};
    std::array<Rms, kTrk> trk{};
    std::array<Rms, kGnss> gnss_err{};
    std::vector<Passage> passages;
    int loops = 0;
    double max_cross = 0, max_alt = 0;
    int first_index = -1;
    int last_index = -1;
    Nanos last_sample = -1;
    Nanos window_start = -1;
    LandingReport landing;
  } f_;
};

}  // namespace tern::core
