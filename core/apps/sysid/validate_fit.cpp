// core/apps/sysid/validate_fit.cpp: a simulated channel against the measured one, NRMSE and
// Theil's U over the scored samples (validate.hpp: definitions and sources).
#include <algorithm>
#include <cmath>
#include <limits>

#include "sysid/validate.hpp"
#include "tern/math.hpp"

namespace tern::core::sysid {

const std::array<ChannelSpec, kChannels> kChannelSpecs = {{
    {"p", "rad/s", false, &FlightSeries::p},
    {"q", "rad/s", false, &FlightSeries::q},
    {"r", "rad/s", false, &FlightSeries::r},
    {"Va", "m/s", false, &FlightSeries::Va},
    {"alpha", "rad", true, &FlightSeries::alpha},
    {"beta", "rad", true, &FlightSeries::beta},
    {"phi", "rad", true, &FlightSeries::phi},
    {"theta", "rad", true, &FlightSeries::theta},
}};

ChannelFit channel_fit(const std::vector<double>& measured, const std::vector<double>& predicted, const std::vector<Window>& windows,
                       bool angle) {
  // sums over the scored samples: y, y^2, yhat^2, e^2 (yhat taken within pi of y for an angle)
  double sum_y = 0, sum_yy = 0, sum_hh = 0, sum_ee = 0;
  std::size_t n = 0;
  for (const Window& w : windows)
    for (std::size_t k = w.begin + 1; k < w.end; ++k) {
      const double y = measured[k];
      const double e = angle ? wrap_pi(predicted[k] - y) : predicted[k] - y;
      const double yhat = y + e;
      sum_y += y, sum_yy += y * y, sum_hh += yhat * yhat, sum_ee += e * e;
      ++n;
    }
  ChannelFit f;
  f.samples = n;
  if (n == 0) {
    f.rms_error = f.std_measured = f.nrmse = f.theil_u = std::numeric_limits<double>::quiet_NaN();
    return f;
  }
  const double N = static_cast<double>(n);
  const double mean = sum_y / N;
  f.rms_error = std::sqrt(sum_ee / N);
  f.std_measured = std::sqrt(std::max(0.0, sum_yy / N - mean * mean));
  f.nrmse = f.std_measured > 0.0 ? f.rms_error / f.std_measured : std::numeric_limits<double>::quiet_NaN();
  const double scale = std::sqrt(sum_yy / N) + std::sqrt(sum_hh / N);
  f.theil_u = scale > 0.0 ? f.rms_error / scale : std::numeric_limits<double>::quiet_NaN();
  return f;
}

}  // namespace tern::core::sysid
