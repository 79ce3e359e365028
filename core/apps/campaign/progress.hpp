// core/apps/campaign/progress.hpp: the campaign's progress line: flights done of the total,
// failures so far, ETA. On a terminal it is redrawn in place (stderr); otherwise a line is
// printed at every tenth of the flights.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tern::campaign {

class Progress {
 public:
  /// `total` flights to fly now, `already` finished before (a resumed campaign).
  Progress(std::size_t total, std::size_t already);
  /// One flight ended; `failed`: it failed its criteria or left no summary.
  void done(bool failed);
  /// Ends the line on a terminal.
  void finish();

 private:
  void draw();
  std::size_t total_, already_, done_ = 0, failed_ = 0, last_decile_ = 0;
  std::int64_t start_ns_;
  bool tty_;
};

}  // namespace tern::campaign
