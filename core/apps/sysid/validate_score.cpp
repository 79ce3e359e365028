// core/apps/sysid/validate_score.cpp: one aircraft file scored on a flight series: the windows'
// simulation, each channel's fit and the one-step residuals (validate.hpp).
#include "sysid/validate.hpp"

namespace tern::core::sysid {

AircraftScore score_aircraft(const FlightSeries& s, const Aircraft& ac, const std::string& file, const std::vector<Window>& windows,
                             const ValidateOptions& o) {
  AircraftScore score;
  score.file = file;
  score.name = ac.name;
  score.servo_tau = ac.servo_tau;
  score.prediction = simulate_windows(s, ac, windows, o);
  for (std::size_t c = 0; c < kChannels; ++c)
    score.fit[c] = channel_fit(s.*kChannelSpecs[c].measured, score.prediction.channel[c], windows, kChannelSpecs[c].angle);
  score.one_step = one_step_residuals(s, ac, windows);
  return score;
}

}  // namespace tern::core::sysid
