// emulator/truth_log.hpp: --truth FILE of the FCU programs (tern-fcu-emulator, tern-fcu-sil): the
// world's true state, for benchmarks and tests that compare a flight through an FCU with the
// direct sim_aero flight (whose flight log has a truth topic). The columns are a subset of the
// flight log's truth.csv, same names and units; one row every `every`-th loop (50 Hz at 400 Hz).
// t is the world's time since power-up, which is the flight time in lockstep (the plugin takes
// the FCU's first IMU sample as the flight's first step). Never read by the autopilot.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "tern/aero/model.hpp"
#include "tern/math.hpp"
#include "tern_sim_aero/simulator.hpp"

namespace tern::fcu::emulator {

class TruthLog {
 public:
  /// Opens (truncates) the file; throws std::runtime_error naming it when that fails.
  explicit TruthLog(const std::string& file, int every = 8) : f_(std::fopen(file.c_str(), "w"), &std::fclose), every_(every) {
    if (!f_) throw std::runtime_error("--truth " + file + ": cannot open for writing");
    std::fputs(
        "t [s],p_n [m],p_e [m],p_d [m],v_n [m/s],v_e [m/s],v_d [m/s],phi [rad],theta [rad],psi [rad],Va [m/s],chi [rad],"
        "w_n [m/s],w_e [m/s],w_d [m/s]\n",
        f_.get());
  }
  /// One row at time t (ns) every `every` calls; Va from the simulator's air data at this state.
  void write(std::int64_t t, const sim::Simulator& sim, double Va) {
    if (n_++ % every_ != 0) return;
    const sim::StateVector& x = sim.state();
    const Eigen::Quaterniond q = sim::attitude(x);
    const Eigen::Vector3d v = q * Eigen::Vector3d(x[sim::U], x[sim::V], x[sim::W]);
    const Eigen::Vector3d e = tern::euler_from_quaternion(q);
    const Eigen::Vector3d w = sim.wind_ned();
    std::fprintf(f_.get(), "%.9f,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
                 static_cast<double>(t) * 1e-9, x[sim::PN], x[sim::PE], x[sim::PD], v.x(), v.y(), v.z(), e.x(), e.y(), e.z(), Va,
                 std::atan2(v.y(), v.x()), w.x(), w.y(), w.z());
  }

 private:
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f_;
  int every_;
  std::uint64_t n_ = 0;
};

}  // namespace tern::fcu::emulator
