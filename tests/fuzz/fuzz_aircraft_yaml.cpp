// fuzz_aircraft_yaml: libFuzzer target for the aircraft file loader (sdk/include/tern/aircraft.hpp
// load_aircraft), as `tern check`, the simulator, the estimator, fcu_serial and the campaigns read
// an aircraft file: the bounded YAML load (tern/input_file.hpp: a regular file of at most 16 MiB,
// at most 100 000 nodes with aliases expanded), then tern's format or ROSflight's `*_dynamics.yaml`
// (told apart by a `ros__parameters:` map), every section's keys and plausible ranges, and
// validate_aircraft (inertia, the triangle inequality, gear and hard points). Any bytes: an
// aircraft whose numbers the model can use (every value finite, mass, inertia and geometry
// positive, the inertia's Gamma coefficients finite, at least one wheel), or std::runtime_error
// whose one line starts with the file's path; never a crash, a hang, another exception or an
// error that does not name the file. The file lies in a directory of its own under TMPDIR;
// nothing is written.
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "fuzz_input.hpp"
#include "tern/aircraft.hpp"

namespace {

bool finite(double v) { return std::isfinite(v); }

/// What the model divides by or integrates: finite, and positive where it must be.
void check(const tern::Aircraft& ac) {
  if (!(ac.mass > 0 && ac.Jx > 0 && ac.Jy > 0 && ac.Jz > 0 && ac.rho > 0 && ac.S > 0 && ac.b > 0 && ac.c > 0)) __builtin_trap();
  if (!finite(ac.mass + ac.Jx + ac.Jy + ac.Jz + ac.Jxz + ac.rho + ac.S + ac.b + ac.c + ac.e + ac.M + ac.alpha0)) __builtin_trap();
  if (!(ac.Jx * ac.Jz - ac.Jxz * ac.Jxz > 0)) __builtin_trap();
  const tern::InertiaGammas g = tern::inertia_gammas(ac);
  if (!finite(g.G1 + g.G2 + g.G3 + g.G4 + g.G5 + g.G6 + g.G7 + g.G8)) __builtin_trap();
  if (!finite(ac.AR()) || !(ac.AR() > 0)) __builtin_trap();
  const auto& a = ac.aero;
  for (double v :
       {a.C_L_0,         a.C_L_alpha,   a.C_L_q,       a.C_L_delta_e, a.C_D_0,       a.C_D_alpha,   a.C_D_p,      a.C_D_q,
        a.C_D_delta_e,   a.C_m_0,       a.C_m_alpha,   a.C_m_q,       a.C_m_delta_e, a.C_Y_0,       a.C_Y_beta,   a.C_Y_p,
        a.C_Y_r,         a.C_Y_delta_a, a.C_Y_delta_r, a.C_ell_0,     a.C_ell_beta,  a.C_ell_p,     a.C_ell_r,    a.C_ell_delta_a,
        a.C_ell_delta_r, a.C_n_0,       a.C_n_beta,    a.C_n_p,       a.C_n_r,       a.C_n_delta_a, a.C_n_delta_r})
    if (!finite(v)) __builtin_trap();
  const auto& p = ac.prop;
  if (!(p.D_prop > 0 && p.K_Q > 0 && p.R_motor > 0 && p.V_max > 0 && p.C_Q_0 > 0)) __builtin_trap();
  if (!finite(p.D_prop + p.C_T_0 + p.C_T_1 + p.C_T_2 + p.C_Q_0 + p.C_Q_1 + p.C_Q_2 + p.K_Q + p.R_motor + p.i0 + p.V_max)) __builtin_trap();
  if (!(ac.max_delta_a > 0 && ac.max_delta_e > 0 && ac.max_delta_r > 0) || !finite(ac.max_delta_a + ac.max_delta_e + ac.max_delta_r))
    __builtin_trap();
  if (ac.gear.points.empty()) __builtin_trap();
  for (const auto& r : ac.gear.points)
    if (!r.allFinite()) __builtin_trap();
  for (const auto& [name, r] : ac.gear.structure)
    if (!r.allFinite()) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = tern::fuzz::in_dir(data, size, "aircraft.yaml");
  const std::string path = file.string();
  try {
    check(tern::load_aircraft(path));
  } catch (const std::runtime_error& e) {
    tern::fuzz::note(e);
    if (std::string(e.what()).rfind(path + ":", 0) != 0) __builtin_trap();  // one line naming the file
  }
  return 0;
}
