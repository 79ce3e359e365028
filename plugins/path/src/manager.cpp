// Path manager, Beard & McLain, ch. 11 (Alg. 5, 6, 8). See manager.hpp.
#include "tern/path/manager.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "tern/math.hpp"

namespace tern::path {

namespace {
using tern::kPi;

std::string fmt(double v, int decimals = 1) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}

bool same(const MissionPoint& a, const MissionPoint& b) {
  return a.w == b.w && a.chi_d == b.chi_d && a.use_chi == b.use_chi && a.Va_d == b.Va_d && a.Vg_min == b.Vg_min && a.type == b.type &&
         a.loiter.radius == b.loiter.radius && a.loiter.direction == b.loiter.direction && a.loiter.time == b.loiter.time &&
         a.loiter.turns == b.loiter.turns && a.loiter.to_altitude == b.loiter.to_altitude && a.land.glide_slope == b.land.glide_slope &&
         a.land.flare_height == b.land.flare_height && a.land.decision_height == b.land.decision_height;
}

bool orbits(const MissionPoint& w) { return w.type == ItemType::loiter || w.type == ItemType::return_home; }
bool lands(const MissionPoint& w) { return w.type == ItemType::land; }

Vec3 unit3(const Vec3& from, const Vec3& to, const Vec3& fallback) {
  const Vec3 d = to - from;
  if (d.head<2>().norm() < 1e-9) return fallback;
  return d.normalized();
}
}  // namespace

PathManager::PathManager(ManagerConfig config, Message warn, Message info) : warn_(std::move(warn)), info_(std::move(info)) {
  set_config(config);
}

void PathManager::set_config(const ManagerConfig& c) {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw std::invalid_argument(std::string("path manager: ") + name + " must be finite and > 0, got " + fmt(v, 6));
  };
  positive(c.R_min, "R_min");
  positive(c.default_airspeed, "default_airspeed");
  positive(c.min_separation, "min_separation");
  positive(c.altitude_band, "altitude_band");
  if (!std::isfinite(c.default_altitude)) throw std::invalid_argument("path manager: default_altitude must be finite");
  if (!(c.turn_bank >= 0.0 && c.turn_bank <= 1.4))
    throw std::invalid_argument("path manager: turn_bank must be in [0, 1.4] rad, got " + fmt(c.turn_bank, 6));
  if (c.land_attempts < 1) throw std::invalid_argument("path manager: land_attempts must be >= 1, got " + std::to_string(c.land_attempts));
  if (!(c.flare_time >= 0.0 && c.flare_time <= 30.0))
    throw std::invalid_argument("path manager: flare_time must be in [0, 30] s, got " + fmt(c.flare_time, 6));
  cfg_ = c;
  loop_ = raw_loop_ && !cfg_.orbit_last;
}

bool PathManager::first_notice(const std::string& key) {
  if (!warned_.insert(key).second) return false;  // once per list
  // and at most once per kRewarnInterval: a coordination plugin re-sending lists of one shape
  // (coord_rendezvous: every few seconds) would otherwise repeat the same notices every time
  const auto last = warned_at_.find(key);
  if (last != warned_at_.end() && now_ - last->second < kRewarnInterval) return false;
  warned_at_[key] = now_;
  return true;
}

void PathManager::warn_once(const std::string& key, const std::string& text) {
  if (first_notice(key) && warn_) warn_(text);
}

void PathManager::inform_once(const std::string& key, const std::string& text) {
  if (first_notice(key) && info_) info_(text);
}

double PathManager::airspeed(const MissionPoint& w) const { return airspeed_along(w, Vec3::Zero()); }

double PathManager::airspeed_along(const MissionPoint& w, const Vec3& q) const {
  const double Va = (std::isfinite(w.Va_d) && w.Va_d > 0.0) ? w.Va_d : cfg_.default_airspeed;
  if (!(w.Vg_min > 0.0) || lands(w)) return Va;
  if (q.head<2>().norm() < 1e-9) return std::max(Va, w.Vg_min + wind_.head<2>().norm());  // every course
  return std::max(Va, (w.Vg_min * q.head<2>().normalized() - wind_.head<2>()).norm());
}

void PathManager::set_wind(const Vec3& wind) {
  if (wind.head<2>().allFinite()) wind_ = Vec3(wind.x(), wind.y(), 0.0);
}

double PathManager::planned_radius(double Va, double chi0, double sweep) const {
  if (!(cfg_.turn_bank > 0.0)) return cfg_.R_min;
  return std::max(cfg_.R_min, wind_turn_radius(Va, wind_, chi0, sweep, cfg_.turn_bank));
}

int PathManager::target() const {
  if (mode_ == Mode::origin_orbit || wps_.empty()) return -1;
  return wps_[target_].index;
}

bool PathManager::same_prefix(const std::vector<MissionPoint>& list, bool loop) const {
  if (loop != raw_loop_ || list.size() < raw_.size()) return false;
  for (std::size_t i = 0; i < raw_.size(); ++i)
    if (!same(list[i], raw_[i])) return false;
  return true;
}

void PathManager::set_waypoints(const std::vector<MissionPoint>& list, bool loop, bool immediate, int loops) {
  loops = std::max(loops, 0);
  if (pending_ || (mode_ == Mode::route && !need_adopt_ && !immediate && !list.empty()))
    pending_loops_ = loops;  // a list that waits for the next decision (or extends this one: loops unchanged below)
  else
    raw_loops_ = loops;
  if (immediate && !list.empty()) {
    raw_loops_ = loops;
    pending_.reset();
    raw_ = list;
    raw_loop_ = loop;
    need_adopt_ = true;
    adopt_first_ = 0;
    if (info_) info_("new mission of " + std::to_string(list.size()) + " item(s): flown now");
    return;
  }
  if (list.empty()) {
    raw_.clear();
    raw_loop_ = loop;
    pending_.reset();
    need_adopt_ = false;
    wps_.clear();
    mode_ = Mode::origin_orbit;
    stage_ = Stage::orbit;
    if (info_) info_("no waypoints: orbiting the origin");
    return;
  }
  if (pending_) {  // a replacement is already waiting for the next decision: this one replaces it
    pending_.emplace(list, loop);
    return;
  }
  const bool extends = !raw_.empty() && same_prefix(list, loop);
  if (extends && list.size() == raw_.size() && !need_adopt_) return;  // the same list again
  if (mode_ == Mode::route && !need_adopt_) {
    if (extends) {
      // Same mission, more waypoints: keep flying the current segment; the new ones come at
      // their turn.
      const int current = wps_[target_].index;
      std::vector<Entry> cleaned = clean(list);
      for (std::size_t k = 0; k < cleaned.size(); ++k) {
        if (cleaned[k].index == current) {
          raw_ = list;
          wps_ = std::move(cleaned);
          target_ = k;
          if (info_) info_("mission extended to " + std::to_string(list.size()) + " waypoints");
          return;
        }
      }
      // The target vanished (not for a true extension): replace at the next decision below.
    }
    pending_.emplace(list, loop);
    if (info_) info_("new mission of " + std::to_string(list.size()) + " waypoints: flown from the next waypoint decision");
    return;
  }
  // Orbiting (origin, single waypoint, mission complete) or not started: take it now.
  int first = 0;
  if (extends && mode_ == Mode::waypoint_orbit && !wps_.empty()) first = wps_[target_].index + 1;
  raw_ = list;
  raw_loop_ = loop;
  need_adopt_ = true;
  adopt_first_ = first;
}

std::vector<PathManager::Entry> PathManager::clean(const std::vector<MissionPoint>& list) {
  std::vector<Entry> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    Entry e{list[i], static_cast<int>(i)};
    if (e.wp.type == ItemType::return_home) e.wp.w.head<2>().setZero();  // home
    if (!e.wp.w.allFinite()) {
      warn_once("nan" + std::to_string(i), "waypoint " + std::to_string(i) + " has a non-finite position: skipped");
      continue;
    }
    if (e.wp.use_chi && !std::isfinite(e.wp.chi_d)) {
      warn_once("chi" + std::to_string(i), "waypoint " + std::to_string(i) + " has a non-finite chi_d: flown without it");
      e.wp.use_chi = false;
    }
    if (!out.empty() && !orbits(e.wp) && !orbits(out.back().wp)) {
      const double d = horizontal_distance(out.back().wp.w, e.wp.w);
      if (d < cfg_.min_separation) {
        warn_once("rep" + std::to_string(i), "waypoint " + std::to_string(i) + " repeats waypoint " + std::to_string(out.back().index) +
                                                 " (" + fmt(d, 2) + " m apart): skipped");
        continue;
      }
    }
    out.push_back(e);
  }
  if (loop_ && out.size() > 1 && !orbits(out.back().wp) && !orbits(out.front().wp) && !lands(out.back().wp)) {
    const double d = horizontal_distance(out.back().wp.w, out.front().wp.w);
    if (d < cfg_.min_separation) {
      warn_once("rep" + std::to_string(out.back().index), "waypoint " + std::to_string(out.back().index) + " repeats waypoint " +
                                                              std::to_string(out.front().index) + " where the loop closes: skipped");
      out.pop_back();
    }
  }
  return out;
}

void PathManager::adopt(const std::vector<MissionPoint>& list, bool loop, const Vec3& p, double chi, int first) {
  raw_ = list;
  raw_loop_ = loop;
  loop_ = loop && !cfg_.orbit_last;
  warned_.clear();
  loops_ = loop_ ? raw_loops_ : 0;
  loops_done_ = 0;
  approach_.reset();
  approaches_ = 0;
  land_abandoned_ = false;
  wps_ = clean(list);
  passed_.reserve(passed_.size() + wps_.size());
  if (wps_.empty()) {
    warn_once("none", "no usable waypoint in a list of " + std::to_string(list.size()) + ": orbiting the origin");
    mode_ = Mode::origin_orbit;
    stage_ = Stage::orbit;
    return;
  }
  if (wps_.size() == 1 && (orbits(wps_[0].wp) || lands(wps_[0].wp))) {
    start_route(0, p, chi);
    return;
  }
  if (wps_.size() == 1) {
    warn_once("one", "one-waypoint mission: orbiting waypoint " + std::to_string(wps_[0].index) + " (radius " + fmt(cfg_.R_min) + " m)");
    mode_ = Mode::waypoint_orbit;
    stage_ = Stage::orbit;
    target_ = 0;
    return;
  }
  if (wps_.size() == 2 && !lands(wps_.back().wp)) {
    if (loop_)
      warn_once("two", "two-waypoint mission: flying back and forth, turning around beyond each waypoint");
    else
      warn_once("two", "two-waypoint mission: flying to both waypoints, then orbiting the last");
  }
  std::size_t k = 0;
  while (k < wps_.size() && wps_[k].index < first) ++k;
  if (k == wps_.size()) {
    if (!loop_) {  // nothing left to fly: orbit the last waypoint
      mode_ = Mode::waypoint_orbit;
      stage_ = Stage::orbit;
      target_ = wps_.size() - 1;
      return;
    }
    k = 0;
  }
  start_route(k, p, chi);
}

void PathManager::start_route(std::size_t first, const Vec3& p, double chi) {
  mode_ = Mode::route;
  target_ = first;
  prev_ = Vec3(p.x(), p.y(), wps_[first].wp.w.z());
  prev_chi_valid_ = false;
  begin_segment(p, chi);
}

// A final land item is not part of the loop: it comes after the last loop (loops > 0) or after
// the one pass of a list that does not loop.
std::optional<std::size_t> PathManager::next_of(std::size_t i) const {
  const bool land_last = !wps_.empty() && lands(wps_.back().wp);
  const std::size_t n_loop = land_last ? wps_.size() - 1 : wps_.size();
  if (i + 1 < n_loop) return i + 1;
  if (i + 1 > n_loop) return std::nullopt;  // the land item: the end
  const bool again = loop_ && n_loop > 1 && (loops_ == 0 || loops_done_ + 1 < loops_);
  if (again) return 0;
  if (land_last) return n_loop;
  return std::nullopt;
}

void PathManager::begin_segment(const Vec3& p, double chi) {
  const MissionPoint& wt = wps_[target_].wp;
  const int idx = wps_[target_].index;
  double R = cfg_.R_min;
  seg_R_ = R;
  if (lands(wt)) {
    begin_land(p, chi);
    return;
  }
  if (orbits(wt)) {
    stage_ = Stage::loiter;
    loiter_on_ = false;
    loiter_swept_ = 0.0;
    seg_R_ = loiter_segment(wps_[target_]).rho;
    if (info_) info_(std::string(item_type_name(wt.type)) + " item " + std::to_string(idx) + ": orbit of radius " + fmt(seg_R_) + " m");
    return;
  }
  if (horizontal_distance(prev_, wt.w) < cfg_.min_separation) {  // already there
    advance(p, chi);
    return;
  }
  const auto nx = next_of(target_);
  if (wt.use_chi) {
    Vec3 ps;
    double chi_s;
    if (prev_chi_valid_) {
      ps = prev_;
      chi_s = prev_chi_;
    } else {
      ps = Vec3(p.x(), p.y(), prev_.z());
      chi_s = std::isfinite(chi) ? chi : std::atan2(wt.w.y() - p.y(), wt.w.x() - p.x());
    }
    R = planned_radius(airspeed(wt), 0.0, 2.0 * kPi);
    seg_R_ = R;
    dubins_ = dubins_path(ps, chi_s, wt.w, wt.chi_d, R);
    if (dubins_.close)
      warn_once("dubins" + std::to_string(idx), "waypoint " + std::to_string(idx) + ": Dubins path starts " +
                                                    fmt(horizontal_distance(ps, wt.w)) + " m away, closer than 2 R_min = " + fmt(2 * R) +
                                                    " m: flying the shortest possible type (" +
                                                    std::string(dubins_type_name(dubins_.type)) + ", " + fmt(dubins_.length) + " m)");
    // Alg. 8 state 1 waits until the aircraft is behind z1; when the start arc is shorter than
    // half a circle the aircraft (at ps) already is, and waiting could cost a full circle when
    // the arc is ~0 and the aircraft has just passed z1.
    stage_ = dubins_.arc_s < kPi ? Stage::dubins_2 : Stage::dubins_1;
    return;
  }
  const Vec3 q_in = Vec3(wt.w.x() - prev_.x(), wt.w.y() - prev_.y(), 0.0).normalized();
  switch_z_ = wt.w;
  switch_n_ = q_in;
  stage_ = Stage::line;
  // last, or a Dubins path, an orbit or a landing's Dubins path follows: pass over it
  if (!nx || wps_[*nx].wp.use_chi || orbits(wps_[*nx].wp) || lands(wps_[*nx].wp)) return;
  const Vec3& w_next = wps_[*nx].wp.w;
  if (cfg_.corner == ManagerConfig::Corner::fillet) {
    if (cfg_.turn_bank > 0.0 && horizontal_distance(wt.w, w_next) > 0.0) {
      // The turn sweeps the courses from the incoming to the outgoing leg.
      const Vec3 q_out = Vec3(w_next.x() - wt.w.x(), w_next.y() - wt.w.y(), 0.0).normalized();
      const double cross = q_in.x() * q_out.y() - q_in.y() * q_out.x();
      const double turn = std::acos(std::clamp(q_in.dot(q_out), -1.0, 1.0));
      const double Va = std::max(airspeed(wt), airspeed(wps_[*nx].wp));
      const double R_wind = planned_radius(Va, std::atan2(q_in.y(), q_in.x()), cross >= 0.0 ? turn : -turn);
      // Tangent points within half of each leg: offset = R / tan(varrho / 2) = R tan(turn / 2).
      const double half_leg = 0.5 * std::min(horizontal_distance(prev_, wt.w), horizontal_distance(wt.w, w_next));
      const double tan_half_turn = std::tan(0.5 * turn);
      const double R_fit = tan_half_turn > 1e-9 ? half_leg / tan_half_turn : R_wind;
      R = std::max(cfg_.R_min, std::min(R_wind, R_fit));
      // information: the turn is flown tighter, at more bank (tan phi grows as 1 / R at one speed)
      if (R_wind > R + 1e-6)
        inform_once("bank" + std::to_string(idx), "waypoint " + std::to_string(idx) + ": the turn needs a radius of " + fmt(R_wind) +
                                                      " m for " + fmt(cfg_.turn_bank * 180.0 / kPi) +
                                                      " deg of bank in the wind; its legs leave room for " + fmt(R_fit) + " m: flying " +
                                                      fmt(R) + " m, about " +
                                                      fmt(std::atan(std::tan(cfg_.turn_bank) * R_wind / R) * 180.0 / kPi) + " deg of bank");
      seg_R_ = R;
    }
    fillet_ = compute_fillet(prev_, wt.w, w_next, R);
    if (fillet_.kind == Fillet::Kind::fillet) {
      stage_ = Stage::fillet_line;
    } else if (fillet_.kind == Fillet::Kind::too_sharp) {
      const double turn_deg = (kPi - fillet_.varrho) * 180.0 / kPi;
      warn_once("sharp" + std::to_string(idx),
                "waypoint " + std::to_string(idx) + ": the " + fmt(turn_deg, 0) + " deg corner needs " +
                    (std::isfinite(fillet_.offset) ? fmt(fillet_.offset) + " m" : std::string("unbounded room")) +
                    " of leg for a fillet of radius " + fmt(R) + " m: flying over the waypoint, then turning");
    }
    return;
  }
  const Vec3 q_out = Vec3(w_next.x() - wt.w.x(), w_next.y() - wt.w.y(), 0.0).normalized();
  switch_n_ = line_switch_normal(q_in, q_out);
  if ((q_in + q_out).norm() < 1e-6)
    warn_once("back" + std::to_string(idx),
              "waypoint " + std::to_string(idx) + ": the path doubles back (180 deg): switching when the aircraft passes it");
}

void PathManager::advance(const Vec3& p, double chi) {
  passed_.push_back(wps_[target_].index);
  if (info_) info_("passed waypoint " + std::to_string(wps_[target_].index));
  const bool was_dubins = stage_ == Stage::dubins_5 || stage_ == Stage::dubins_4;
  if (pending_) {
    auto next = std::move(*pending_);
    pending_.reset();
    raw_loops_ = pending_loops_;
    adopt(next.first, next.second, p, chi, 0);
    return;
  }
  const auto nx = next_of(target_);
  if (!nx) {
    mode_ = Mode::waypoint_orbit;
    stage_ = Stage::orbit;
    if (info_) info_("mission complete: orbiting waypoint " + std::to_string(wps_[target_].index));
    return;
  }
  prev_ = wps_[target_].wp.w;
  prev_chi_valid_ = was_dubins;
  prev_chi_ = wps_[target_].wp.chi_d;
  if (*nx == 0 && target_ != 0) {
    ++loops_done_;
    if (info_ && loops_ > 0) info_("loop " + std::to_string(loops_done_) + " of " + std::to_string(loops_) + " flown");
  }
  target_ = *nx;
  begin_segment(p, chi);
}

PathSegment PathManager::orbit_segment(const Vec3& c, int index, double Va) const {
  PathSegment s;
  s.type = PathSegment::Type::orbit;
  s.c = c;
  s.rho = planned_radius(Va, 0.0, 2.0 * kPi);
  s.lambda = 1;
  s.Va_d = Va;
  s.waypoint_index = index;
  return s;
}

PathSegment PathManager::loiter_segment(const Entry& e) const {
  PathSegment s = orbit_segment(e.wp.w, e.index, airspeed(e.wp));
  if (e.wp.loiter.radius > 0.0) s.rho = e.wp.loiter.radius;
  s.lambda = e.wp.loiter.direction >= 0 ? 1 : -1;
  return s;
}

double PathManager::loiter_turns_flown() const { return loiter_swept_ / (2.0 * kPi); }

bool PathManager::loiter_done(const Vec3& p, double t) {
  const Entry& e = wps_[target_];
  const double R = loiter_segment(e).rho;
  const Vec3 d = p - e.wp.w;
  const double bearing = std::atan2(d.y(), d.x());
  if (!loiter_on_) {
    if (std::fabs(d.head<2>().norm() - R) > kOnOrbit * R) return false;
    loiter_on_ = true;
    loiter_since_ = t;
    loiter_swept_ = 0.0;
    loiter_angle_ = bearing;
    if (info_) info_(std::string(item_type_name(e.wp.type)) + " item " + std::to_string(e.index) + ": on the orbit");
  }
  loiter_swept_ += wrap_pi(bearing - loiter_angle_) * (e.wp.loiter.direction >= 0 ? 1.0 : -1.0);
  loiter_angle_ = bearing;
  const LoiterSpec& l = e.wp.loiter;
  if (e.wp.type != ItemType::loiter) return false;  // return_home: until the mission changes
  return (l.time > 0.0 && t - loiter_since_ >= l.time) || (l.turns > 0.0 && loiter_swept_ >= 2.0 * kPi * l.turns) ||
         (l.to_altitude && std::fabs(d.z()) <= cfg_.altitude_band);
}

PathSegment PathManager::current_segment() const {
  if (mode_ == Mode::origin_orbit) return orbit_segment(Vec3(0.0, 0.0, -cfg_.default_altitude), -1, cfg_.default_airspeed);
  const MissionPoint& wt = wps_[target_].wp;
  const int idx = wps_[target_].index;
  if (lands(wt)) return land_segment(wps_[target_]);
  if (mode_ == Mode::waypoint_orbit || stage_ == Stage::loiter)
    return orbits(wt) ? loiter_segment(wps_[target_]) : orbit_segment(wt.w, idx, airspeed(wt));
  PathSegment s;
  s.Va_d = airspeed(wt);
  s.waypoint_index = idx;
  auto orbit = [&](const Vec3& c, int lambda) {
    s.type = PathSegment::Type::orbit;
    s.c = c;
    s.rho = seg_R_;
    s.lambda = lambda;
  };
  switch (stage_) {
    case Stage::line:
    case Stage::fillet_line:
      s.type = PathSegment::Type::line;
      s.r = prev_;
      s.q = unit3(prev_, wt.w, switch_n_);
      s.Va_d = airspeed_along(wt, s.q);
      break;
    case Stage::fillet_orbit: orbit(fillet_.c, fillet_.lambda); break;
    case Stage::dubins_1:
    case Stage::dubins_2: orbit(dubins_.cs, dubins_.lambda_s); break;
    case Stage::dubins_3:
      s.type = PathSegment::Type::line;
      s.r = dubins_.z1;
      s.q = unit3(dubins_.z1, dubins_.z2, dubins_.q1);
      s.Va_d = airspeed_along(wt, s.q);
      break;
    case Stage::dubins_4:
    case Stage::dubins_5: orbit(dubins_.ce, dubins_.lambda_e); break;
    case Stage::orbit: return orbit_segment(wt.w, idx, airspeed(wt));
    case Stage::loiter: return loiter_segment(wps_[target_]);  // (returned above already)
    case Stage::land_final:
    case Stage::go_around: break;  // land items: land_segment() (returned above)
  }
  return s;
}

// ---- land items ----------------------------------------------------------------------------

void PathManager::set_home_altitude(double h) {
  if (std::isfinite(h)) home_h_ = h;
}

void PathManager::set_runway_down(double d) {
  if (std::isfinite(d)) runway_d_ = d;
}

void PathManager::begin_land(const Vec3& p, double chi) {
  const Entry& e = wps_[target_];
  Vec3 td = e.wp.w;
  td.z() -= home_h_;
  const double entry_d = approach_ ? approach_->entry.z() : prev_.z();
  const double Vg = runway_ground_speed(airspeed(e.wp), wind_, e.wp.chi_d);
  approach_ = plan_approach(td, e.wp.chi_d, e.wp.land, entry_d, aim_offset(Vg, cfg_.flare_time, e.wp.land));
  if (approach_->raised)
    warn_once("landlow" + std::to_string(e.index), "land item " + std::to_string(e.index) + ": the approach altitude is raised to " +
                                                       fmt(-approach_->entry.z()) + " m (" + fmt(kMinEntryHeights, 0) +
                                                       " decision heights above the touchdown point)");
  if (land_abandoned_) {
    mode_ = Mode::waypoint_orbit;
    stage_ = Stage::orbit;
    return;
  }
  const bool from_dubins = prev_chi_valid_ && approaches_ == 0 && stage_ != Stage::go_around;
  const Vec3 ps = from_dubins ? Vec3(prev_.x(), prev_.y(), approach_->entry.z()) : Vec3(p.x(), p.y(), approach_->entry.z());
  const double chi_s = from_dubins ? prev_chi_ : (std::isfinite(chi) ? chi : approach_->heading);
  seg_R_ = planned_radius(airspeed(e.wp), 0.0, 2.0 * kPi);
  dubins_ = dubins_path(ps, chi_s, approach_->entry, approach_->heading, seg_R_);
  stage_ = dubins_.arc_s < kPi ? Stage::dubins_2 : Stage::dubins_1;
  if (info_) info_("land item " + std::to_string(e.index) + ": to the approach's entry point (" + fmt(dubins_.length, 0) + " m)");
}

void PathManager::go_around(const Vec3& p) {
  if (mode_ != Mode::route || wps_.empty() || !lands(wps_[target_].wp) || !approach_ || !p.allFinite()) return;
  const int idx = wps_[target_].index;
  if (approaches_ >= cfg_.land_attempts) {
    land_abandoned_ = true;
    mode_ = Mode::waypoint_orbit;
    stage_ = Stage::orbit;
    warn_once("abandon" + std::to_string(idx), "land item " + std::to_string(idx) + ": landing abandoned after " +
                                                   std::to_string(approaches_) + " approaches: orbiting above the touchdown point");
    return;
  }
  const Vec3 h_dir(std::cos(approach_->heading), std::sin(approach_->heading), 0.0);
  go_r_ = Vec3(p.x(), p.y(), approach_->entry.z());
  const double past = std::max(along_runway(*approach_, p), 0.0) + 2.0 * seg_R_;
  go_z_ = approach_->touchdown + past * h_dir;
  stage_ = Stage::go_around;
  if (info_) info_("land item " + std::to_string(idx) + ": go-around after approach " + std::to_string(approaches_));
}

PathSegment PathManager::land_segment(const Entry& e) const {
  PathSegment s;
  s.Va_d = airspeed(e.wp);
  s.waypoint_index = e.index;
  const Approach& a = *approach_;
  if (mode_ == Mode::waypoint_orbit) {  // abandoned
    PathSegment o = orbit_segment(Vec3(a.touchdown.x(), a.touchdown.y(), a.entry.z()), e.index, s.Va_d);
    return o;
  }
  auto orbit = [&](const Vec3& c, int lambda) {
    s.type = PathSegment::Type::orbit;
    s.c = c;
    s.rho = seg_R_;
    s.lambda = lambda;
  };
  s.type = PathSegment::Type::line;
  switch (stage_) {
    case Stage::land_final:
      s.r = a.aim;
      if (runway_d_) s.r.z() = *runway_d_;  // the glide path moved onto the runway the range finder sees
      s.q = a.q;
      s.landing = true;
      s.flare_height = e.wp.land.flare_height;
      s.decision_height = e.wp.land.decision_height;
      s.attempt = approaches_;
      break;
    case Stage::go_around:
      s.r = go_r_;
      s.q = Vec3(std::cos(a.heading), std::sin(a.heading), 0.0);
      break;
    case Stage::dubins_3:
      s.r = dubins_.z1;
      s.q = unit3(dubins_.z1, dubins_.z2, dubins_.q1);
      break;
    case Stage::dubins_4:
    case Stage::dubins_5: orbit(dubins_.ce, dubins_.lambda_e); break;
    default: orbit(dubins_.cs, dubins_.lambda_s); break;  // dubins_1, dubins_2
  }
  return s;
}

PathSegment PathManager::update(const Vec3& p, double chi, double t) {
  now_ = t;
  if (!p.allFinite()) {
    warn_once("state", "aircraft position is not finite: keeping the current segment");
    return have_last_ ? last_ : current_segment();
  }
  if (need_adopt_) {
    need_adopt_ = false;
    adopt(raw_, raw_loop_, p, chi, adopt_first_);
  }
  if (mode_ == Mode::route) {
    switch (stage_) {
      case Stage::line:
        if (in_half_plane(p, switch_z_, switch_n_)) advance(p, chi);
        break;
      case Stage::fillet_line:
        if (in_half_plane(p, fillet_.z1, fillet_.q_in)) stage_ = Stage::fillet_orbit;
        break;
      case Stage::fillet_orbit:
        if (in_half_plane(p, fillet_.z2, fillet_.q_out)) advance(p, chi);
        break;
      case Stage::dubins_1:
        if (in_half_plane(p, dubins_.z1, -dubins_.q1)) stage_ = Stage::dubins_2;
        break;
      case Stage::dubins_2:
        if (in_half_plane(p, dubins_.z1, dubins_.q1)) stage_ = Stage::dubins_3;
        break;
      case Stage::dubins_3:
        if (in_half_plane(p, dubins_.z2, dubins_.q1)) stage_ = dubins_.arc_e < kPi ? Stage::dubins_5 : Stage::dubins_4;
        break;
      case Stage::dubins_4:
        if (in_half_plane(p, dubins_.z3, -dubins_.q3)) stage_ = Stage::dubins_5;
        break;
      case Stage::dubins_5:
        if (!in_half_plane(p, dubins_.z3, dubins_.q3)) break;
        if (lands(wps_[target_].wp)) {
          ++approaches_;
          stage_ = Stage::land_final;
          if (info_)
            info_("land item " + std::to_string(wps_[target_].index) + ": final approach " + std::to_string(approaches_) + ", glide path " +
                  fmt(approach_->length, 0) + " m aimed " + fmt(approach_->aim_offset) + " m before the touchdown point");
        } else {
          advance(p, chi);
        }
        break;
      case Stage::go_around:
        if (in_half_plane(p, go_z_, Vec3(std::cos(approach_->heading), std::sin(approach_->heading), 0.0))) begin_land(p, chi);
        break;
      case Stage::land_final: break;
      case Stage::loiter:
        if (loiter_done(p, t)) advance(p, chi);
        break;
      case Stage::orbit: break;
    }
  }
  last_ = current_segment();
  have_last_ = true;
  return last_;
}

}  // namespace tern::path
