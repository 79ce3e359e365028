// core/apps/replay/replay_source.hpp: plays a sensor log's topics (docs/sensor-log.md: a tern flight log,
// or a real flight `tern import` wrote) back into the port graph, for `tern replay LOG`.
//
// The host's built-in I/O instance `replay` (host/graph/recorded_source.hpp). At configure it reads LOG/topics/<t>.csv for the sensor
// topics imu, gnss, baro, diff_pressure, mag, the controllers' `actuators` (which the estimator's
// side-force model reads; played one tick late, as a feedback edge is seen in flight), the
// simulator's `truth` and another estimator's `reference` (those present; not read when the
// replay compares nothing, as sysid's and validate's estimate), mapping columns by
// name onto the message layout (a unit in brackets must be the layout's; a column the sensor needs
// must be there, an optional one the table lacks keeps the message's default, NaN for the
// reference; the file, the columns and the times within table_limits.hpp's bounds); at each tick it publishes every row whose
// time `t` is <= now, in order, each one a message of its own (several rows of one topic inside one
// tick reach a consumer with a queue each: tern/port.hpp). The replay ends at the first tick at or
// after the last IMU row (end_time()), so that row is played; rows of other topics after that tick
// are not (the summary counts them). The values are bit-exact: the log writes doubles in shortest
// round-trip form. Rows whose time goes backwards are dropped and rows holding NaN are played
// (the estimator rejects them), each kind counted in one warning per file; a last line without a
// line end (a flight killed while writing it) is dropped with one warning; a short row or a cell
// that is not a number is an error naming file, line and column.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "graph/recorded_source.hpp"

namespace tern::core {

class ReplaySource final : public RecordedSource {
 public:
  /// `comparisons`: also play the log's `truth` and `reference` (what `tern replay` scores the
  /// estimate against).
  explicit ReplaySource(std::filesystem::path run_dir, bool comparisons = true);
  ~ReplaySource() override;
  void configure() override;
  void start() override;
  void reset() override { start(); }
  void step(Nanos now) override;
  Nanos end_time() const override { return end_; }
  /// Per topic: `<topic>_rows` (rows read, after the dropped ones) and `<topic>_played` (published
  /// this flight), for the replay report's row account.
  std::vector<std::pair<std::string, double>> summary() const override;

  struct TrackBase {
    virtual ~TrackBase() = default;
    virtual void publish_until(Nanos now) = 0;
    virtual void rewind() = 0;
    virtual Nanos last_time() const = 0;
    virtual std::size_t rows() const = 0;
    virtual std::size_t played() const = 0;
    std::string topic;
    /// Why the CSV's last line was dropped ("" if it was complete).
    virtual const std::string& partial_last_line() const = 0;
    /// Rows dropped (time going backwards) or holding NaN, one line per kind with counts.
    virtual const std::vector<std::string>& warnings() const = 0;
    /// A topic the flight's controllers wrote after the estimator had run (actuators): it is
    /// played back one tick late, as the estimator saw it in flight.
    bool feedback = false;
  };

 private:
  std::filesystem::path dir_;
  bool comparisons_ = true;
  std::vector<std::unique_ptr<TrackBase>> tracks_;
  Nanos end_ = 0;
};

/// HostOptions::replay for the sensor log in `run_dir` (`comparisons`: ReplaySource's).
RecordedSourceFactory replay_source(std::filesystem::path run_dir, bool comparisons = true);

}  // namespace tern::core
