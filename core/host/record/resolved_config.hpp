// core/host/record/resolved_config.hpp: the flight log's config.yaml, the config as flown: every
// parameter's effective value, absolute paths, the phase table, the seed and the duration.
//
// Emitting it (yaml-cpp) is most of what a reset between flights costs (about 5 ms for the
// default mission's 13 kB), and between two episodes of a learning environment only the seed
// changes. ResolvedConfig keeps the last text and emits again only when something it is made of
// changed (a parameter, a library after a swap, the phase table, the duration); a new seed is
// written into the kept text. The text is byte for byte what emitting afresh gives.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "record/flight_report.hpp"

namespace tern::core {

/// config.yaml's text for the flight `f` describes, emitted afresh.
std::string resolved_config_yaml(const FlightFacts& f);

/// resolved_config_yaml, kept between flights (above). One per host; not thread-safe.
class ResolvedConfig {
 public:
  const std::string& text(const FlightFacts& f);

 private:
  std::string inputs_;           // what the kept text was made of, but the seed
  std::string text_;             // the kept text
  std::size_t seed_at_ = 0;      // where its top-level seed's digits start ...
  std::size_t seed_length_ = 0;  // ... and how many (0: not found, emit every time)
};

}  // namespace tern::core
