// path_follower adapter. See adapters.hpp and tern/path/follower.hpp.
#include <cmath>

#include <spdlog/spdlog.h>

#include "adapters.hpp"

namespace tern::path {

void FollowerPlugin::configure() {
  declare(state_, "state", "vehicle state (position, course, airspeed)");
  declare(path_, "current_path", "the segment to follow, from the path manager");
  declare(command_, "controller_command", "Va_c, h_c, chi_c and the orbit roll feed-forward phi_ff");
  // Defaults: ROSplane's Anaconda parameters (rosplane/params/anaconda_autopilot_params.yaml).
  declare(chi_infty_, "chi_infty", 1.2, ParamSpec("rad", 0.01, 1.5707963267948966, "approach course to a line from far away (chi^inf)"));
  declare(k_path_, "k_path", 0.0175, ParamSpec("1/m", 1e-5, 10.0, "line vector-field gain: how sharply the field turns near the line"));
  declare(k_orbit_, "k_orbit", 0.5, ParamSpec("", 0.01, 100.0, "orbit vector-field gain: how sharply the field turns near the orbit"));
}

void FollowerPlugin::step(Nanos now) {
  if (!state_.has_value() || !path_.has_value()) return;
  const auto& s = *state_;
  const auto& p = *path_;
  FollowerInput in;
  in.p = Vec3(s.p_n, s.p_e, s.p_d);
  in.chi = s.chi;
  in.psi = s.psi;
  in.Va = s.Va;
  in.Vg = s.Vg;
  PathSegment seg;
  seg.type = p.path_type == msg::CurrentPath::line ? PathSegment::Type::line : PathSegment::Type::orbit;
  seg.Va_d = p.Va_d;
  seg.r = p.r;
  seg.q = p.q;
  seg.c = p.c;
  seg.rho = p.rho;
  seg.lambda = p.lambda;
  seg.landing = p.landing;
  const bool ok = in.p.allFinite() && std::isfinite(s.chi) && std::isfinite(p.Va_d) && p.r.allFinite() && p.q.allFinite() &&
                  p.c.allFinite() && std::isfinite(p.rho) && (seg.type == PathSegment::Type::line || p.rho > 0.0);
  if (!ok) {
    if (!f_.warned_nan) log().warn("state or current_path is not finite (or orbit radius <= 0): no command this step");
    f_.warned_nan = true;
    return;
  }
  FollowerGains g;
  g.chi_inf = chi_infty_();
  g.k_path = k_path_();
  g.k_orbit = k_orbit_();
  const FollowerCommand c = follow(seg, in, g);
  msg::ControllerCommand out;
  out.stamp = now;
  out.Va_c = c.Va_c;
  out.h_c = c.h_c;
  out.chi_c = c.chi_c;
  out.phi_ff = c.phi_ff;
  out.landing = c.landing;
  out.h_td = c.h_td;
  command_.publish(out);
}

}  // namespace tern::path
