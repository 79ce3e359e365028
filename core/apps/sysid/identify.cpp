// core/apps/sysid/identify.cpp: the equation-error identification (identify.hpp).
#include "sysid/identify.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "sysid/instrumentation.hpp"
#include "sysid/regression.hpp"
#include "sysid/sideslip_instrument.hpp"
#include "tern/math.hpp"
#include "tern_sim_aero/model.hpp"

namespace tern::core::sysid {

namespace {

using Col = std::vector<double>;
using Member = double AeroCoefficients::*;
using M = AeroCoefficients;

/// When a regressor counts as excited: `peak` of |signal| (rates) or the standard deviation of
/// signal less its trim-window means (angles, surfaces) above `threshold`; `what` words the
/// failure ("pitch rate never above 5 deg/s").
struct Excitation {
  const Col* signal = nullptr;
  bool peak = false;
  double threshold = 0.0;
  std::string what;
};

/// One term of a model: coefficient * regressor.
struct Term {
  std::string name;
  Member member = nullptr;
  const Col* x = nullptr;
  Excitation excitation;
  const Col* instrument = nullptr;  ///< the same quantity measured with an independent error (or none)
};

/// The airborne stretches (consecutive samples of the series) and the trim windows in them.
struct Layout {
  std::vector<std::pair<std::size_t, std::size_t>> segments;  ///< [begin, end) of the samples
  std::vector<std::vector<std::size_t>> windows;              ///< samples of each trim window
};

/// s: the longest piece of an airborne stretch transformed at once (a longer stretch is cut into
/// equal pieces): the frequency-domain rows' batches, whose estimates' scatter bounds the error.
constexpr double kMaxSegment = 120.0;

Layout layout_of(const AeroSamples& a, double window_s, double min_segment_s) {
  Layout L;
  std::size_t begin = 0;
  for (std::size_t k = 1; k <= a.size(); ++k) {
    if (k < a.size() && a.source[k] == a.source[k - 1] + 1) continue;
    if (a.t[k - 1] - a.t[begin] >= min_segment_s) {
      // pieces of at most kMaxSegment (equal lengths): the batches of the scatter bound
      const auto pieces = static_cast<std::size_t>(std::ceil((a.t[k - 1] - a.t[begin]) / kMaxSegment));
      for (std::size_t i = 0; i < pieces; ++i)
        L.segments.emplace_back(begin + (k - begin) * i / pieces, begin + (k - begin) * (i + 1) / pieces);
    }
    // trim windows over every stretch, short ones too
    for (std::size_t w = begin; w < k;) {
      std::vector<std::size_t> idx;
      for (; w < k && a.t[w] - a.t[idx.empty() ? w : idx.front()] < window_s; ++w) idx.push_back(w);
      if (a.t[idx.back()] - a.t[idx.front()] >= 0.75 * window_s) L.windows.push_back(std::move(idx));
    }
    begin = k;
  }
  return L;
}

Col window_means(const Col& x, const Layout& L) {
  Col m;
  for (const auto& w : L.windows) {
    double s = 0.0;
    for (const std::size_t k : w) s += x[k];
    m.push_back(s / static_cast<double>(w.size()));
  }
  return m;
}

/// x less its trim-window means (samples outside every window: 0).
Col detrended(const Col& x, const Layout& L) {
  Col d(x.size(), 0.0);
  const Col m = window_means(x, L);
  for (std::size_t i = 0; i < L.windows.size(); ++i)
    for (const std::size_t k : L.windows[i]) d[k] = x[k] - m[i];
  return d;
}

double rms(const Col& x) {
  double s = 0.0;
  for (const double v : x) s += v * v;
  return x.empty() ? 0.0 : std::sqrt(s / static_cast<double>(x.size()));
}

double peak(const Col& x) {
  double m = 0.0;
  for (const double v : x) m = std::max(m, std::abs(v));
  return m;
}

/// The frequency-domain rows of every signal: each segment at the multiples of 1/T in the band.
class Spectra {
 public:
  Spectra(const AeroSamples& a, const Layout& L, double lo, double hi) : a_(a), L_(L), lo_(lo), hi_(hi) {
    Eigen::Index at = 0;
    for (const auto& [b, e] : L_.segments) {
      const Eigen::Index n = static_cast<Eigen::Index>(frequencies(b, e).size());
      rows_.emplace_back(at, n);
      at += n;
    }
  }
  /// (first row, rows) of each segment's frequencies in every spectrum.
  const std::vector<std::pair<Eigen::Index, Eigen::Index>>& segment_rows() const { return rows_; }
  /// The frequencies (Hz) of segment i's rows.
  Col segment_frequencies(std::size_t i) const { return frequencies(L_.segments[i].first, L_.segments[i].second); }
  /// A spectrum made in the frequency domain (an instrument), served as `of(*key)` until forget(key):
  /// the cache is keyed by address, so a key must be forgotten before it goes out of scope.
  void put(const Col* key, Eigen::VectorXcd spectrum) { cache_[key] = std::move(spectrum); }
  void forget(const Col* key) { cache_.erase(key); }
  const Eigen::VectorXcd& of(const Col& x) {
    auto it = cache_.find(&x);
    if (it != cache_.end()) return it->second;
    std::vector<Eigen::VectorXcd> parts;
    Eigen::Index n = 0;
    for (const auto& [b, e] : L_.segments) {
      const Col t(a_.t.begin() + static_cast<std::ptrdiff_t>(b), a_.t.begin() + static_cast<std::ptrdiff_t>(e));
      const Col v(x.begin() + static_cast<std::ptrdiff_t>(b), x.begin() + static_cast<std::ptrdiff_t>(e));
      parts.push_back(fourier(v, t, frequencies(b, e)));
      n += parts.back().size();
    }
    Eigen::VectorXcd all(n);
    Eigen::Index at = 0;
    for (const auto& p : parts) all.segment(at, p.size()) = p, at += p.size();
    return cache_.emplace(&x, std::move(all)).first->second;
  }

 private:
  /// The multiples of 1/T in the band, T the segment's length.
  Col frequencies(std::size_t b, std::size_t e) const {
    const double T = a_.t[e - 1] - a_.t[b];
    Col f;
    for (int m = static_cast<int>(std::ceil(lo_ * T)); m / T <= hi_; ++m) f.push_back(m / T);
    return f;
  }
  const AeroSamples& a_;
  const Layout& L_;
  double lo_, hi_;
  std::map<const Col*, Eigen::VectorXcd> cache_;
  std::vector<std::pair<Eigen::Index, Eigen::Index>> rows_;
};

struct Context {
  const AeroSamples& a;
  const Layout& L;
  const SysidOptions& o;
  Spectra spectra;
  AeroCoefficients& coef;  ///< the identified model so far
  const AeroCoefficients& prior;
  SysidResult& result;
};

CoefficientEstimate& record(Context& c, const Term& t, const std::string& method) {
  CoefficientEstimate e;
  e.name = t.name;
  e.prior = c.prior.*t.member;
  e.estimate = c.coef.*t.member;
  e.method = method;
  e.equation_error = e.estimate;
  c.result.coefficients.push_back(e);
  return c.result.coefficients.back();
}

/// Why a term's regressor was not excited, or "".
std::string unexcited(Context& c, const Term& t) {
  const Excitation& x = t.excitation;
  if (x.signal == nullptr) return "";
  const double level = x.peak ? peak(*x.signal) : rms(detrended(*x.signal, c.L));
  return level > x.threshold ? "" : x.what;
}

/// The jackknife's standard errors of the delete-one-batch estimates `thetas` (p each): sqrt((G - 1) /
/// G sum (theta_(i) - mean)^2). Zero with fewer than three.
Eigen::VectorXd jackknife_se(const std::vector<Eigen::VectorXd>& thetas, Eigen::Index p) {
  Eigen::VectorXd se = Eigen::VectorXd::Zero(p);
  if (thetas.size() < 3) return se;
  const double G = static_cast<double>(thetas.size());
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(p);
  for (const auto& t : thetas) mean += t / G;
  for (const auto& t : thetas) se += (t - mean).cwiseAbs2();
  return (se * (G - 1.0) / G).cwiseSqrt();
}

/// The scatter bound: the delete-one-batch jackknife over the segments (batches of at most
/// kMaxSegment): the regression refitted without each batch in turn, the variance
/// (G - 1) / G sum (theta_(i) - mean)^2 (Efron and Tibshirani, *An Introduction to the Bootstrap*,
/// ch. 11): what the flight's pieces disagree by, which no residual model of one fit sees. Unlike a
/// fit of each batch alone it stays defined when a batch holds no excitation of its own (the take-off's,
/// an instrument weak there). Zero when fewer than three batches hold rows.
Eigen::VectorXd batch_scatter(const Context& c, const Eigen::MatrixXcd& X, const Eigen::VectorXcd& z, const Eigen::MatrixXcd& Z, bool iv) {
  std::vector<Eigen::VectorXd> thetas;
  for (const auto& [first, n] : c.spectra.segment_rows()) {
    if (n == 0 || X.rows() - n <= 3 * X.cols()) continue;
    const Eigen::Index rest = X.rows() - n, tail = X.rows() - first - n;
    Eigen::MatrixXcd Xr(rest, X.cols()), Zr(rest, X.cols());
    Eigen::VectorXcd zr(rest);
    Xr << X.topRows(first), X.bottomRows(tail);
    Zr << Z.topRows(first), Z.bottomRows(tail);
    zr << z.head(first), z.tail(tail);
    thetas.push_back(least_squares_frequency(Xr, zr, iv ? &Zr : nullptr).theta);
  }
  return jackknife_se(thetas, X.cols());
}

/// Why each free term fails after a fit (collinear, poorly determined), by name.
std::map<std::string, std::string> failures(Context& c, const std::vector<Term>& free, const LsEstimate& e, const Eigen::MatrixXd& R) {
  std::map<std::string, std::string> bad;
  for (std::size_t j = 0; j < free.size(); ++j) {
    const auto J = static_cast<Eigen::Index>(j);
    for (std::size_t i = 0; i < free.size(); ++i)
      if (i != j && std::abs(R(J, static_cast<Eigen::Index>(i))) > c.o.max_correlation) {
        bad[free[j].name] = fmt::format("collinear with {} (r = {:.2f})", free[i].name, R(J, static_cast<Eigen::Index>(i)));
        break;
      }
    if (!bad.count(free[j].name) && e.std_error[J] > c.o.max_relative_error * std::abs(e.theta[J]))
      bad[free[j].name] = fmt::format("poorly determined: {:.3g} +- {:.2g}", e.theta[J], e.std_error[J]);
  }
  return bad;
}

/// The prior of a term kept at it is taken as uncertain by this fraction of its value (a model
/// from XFLR5 or the book's sister aircraft: x0.6 .. x1.5); its effect on the estimates fitted
/// beside it is added to their bounds (a consider covariance).
constexpr double kPriorUncertainty = 0.5;

/// z = sum of terms, in the frequency domain over the band. Terms not excited keep the prior (moved
/// to the left side); of those collinear or poorly determined after a fit, the least determined
/// (largest standard error / |estimate|) keeps its prior and the others are fitted again. What the
/// kept priors' uncertainty (kPriorUncertainty) moves the fitted terms by is added to their bounds.
void band_fit(Context& c, const std::string& axis, const Col& z, const std::vector<Term>& terms) {
  std::vector<Term> free;
  std::map<std::string, std::string> why;
  for (const Term& t : terms) {
    const std::string u = unexcited(c, t);
    if (u.empty())
      free.push_back(t);
    else
      why[t.name] = u;
  }
  while (!free.empty()) {
    Eigen::VectorXcd zf = c.spectra.of(z);
    for (const Term& t : terms)
      if (why.count(t.name)) zf -= (c.prior.*t.member) * c.spectra.of(*t.x);
    Eigen::MatrixXcd X(zf.size(), static_cast<Eigen::Index>(free.size())), Z(X.rows(), X.cols());
    bool instrumented = false;
    for (std::size_t j = 0; j < free.size(); ++j) {
      X.col(static_cast<Eigen::Index>(j)) = c.spectra.of(*free[j].x);
      Z.col(static_cast<Eigen::Index>(j)) = c.spectra.of(free[j].instrument != nullptr ? *free[j].instrument : *free[j].x);
      instrumented = instrumented || free[j].instrument != nullptr;
    }
    if (X.rows() <= X.cols())
      throw std::runtime_error(fmt::format("{}: too few frequency rows in {}..{} Hz", axis, c.o.band_lo_hz, c.o.band_hi_hz));
    LsEstimate e = least_squares_frequency(X, zf, instrumented ? &Z : nullptr);
    e.std_error = e.std_error.cwiseMax(batch_scatter(c, X, zf, Z, instrumented));
    // with instruments the estimate rests on Z: collinear instruments leave it undetermined
    const std::map<std::string, std::string> bad = failures(c, free, e, column_correlation(instrumented ? Z : X));
    if (bad.empty()) {
      for (const Term& t : terms) {  // the kept priors as consider parameters
        if (!why.count(t.name)) continue;
        const Eigen::VectorXcd shifted = zf - kPriorUncertainty * (c.prior.*t.member) * c.spectra.of(*t.x);
        const LsEstimate moved = least_squares_frequency(X, shifted, instrumented ? &Z : nullptr);
        e.std_error = (e.std_error.cwiseAbs2() + (moved.theta - e.theta).cwiseAbs2()).cwiseSqrt();
      }
      c.result.fits.push_back({axis, "band", e.r_squared, std::sqrt(e.s2), e.rows});
      for (std::size_t j = 0; j < free.size(); ++j) {
        c.coef.*free[j].member = e.theta[static_cast<Eigen::Index>(j)];
        CoefficientEstimate& r = record(c, free[j], "band");
        r.std_error = e.std_error[static_cast<Eigen::Index>(j)];
        r.identified = true;
      }
      break;
    }
    // one term at a time, the least determined first: of two collinear terms the other may then stand
    std::size_t worst = free.size();
    double worst_ratio = -1.0;
    for (std::size_t j = 0; j < free.size(); ++j) {
      const auto J = static_cast<Eigen::Index>(j);
      const double ratio = e.std_error[J] / std::max(std::abs(e.theta[J]), 1e-300);
      if (bad.count(free[j].name) && (worst == free.size() || ratio > worst_ratio)) worst = j, worst_ratio = ratio;
    }
    why[free[worst].name] = bad.at(free[worst].name);
    free.erase(free.begin() + static_cast<std::ptrdiff_t>(worst));
  }
  for (const Term& t : terms)
    if (why.count(t.name)) {
      c.coef.*t.member = c.prior.*t.member;
      record(c, t, "band").note = why[t.name];
    }
}

/// A bias term from the trim windows: mean of z less the model's other terms.
void bias_fit(Context& c, const std::string& name, Member member, const Col& z, const std::vector<Term>& terms) {
  Col resid(z);
  for (const Term& t : terms)
    for (std::size_t k = 0; k < z.size(); ++k) resid[k] -= (c.coef.*t.member) * (*t.x)[k];
  const Col m = window_means(resid, c.L);
  Eigen::MatrixXd X = Eigen::MatrixXd::Ones(static_cast<Eigen::Index>(m.size()), 1);
  const Eigen::VectorXd zz = Eigen::Map<const Eigen::VectorXd>(m.data(), static_cast<Eigen::Index>(m.size()));
  const LsEstimate e = least_squares(X, zz, 3);
  c.coef.*member = e.theta[0];
  CoefficientEstimate& r = record(c, {name, member, nullptr, {}}, "trim");
  r.std_error = e.std_error[0];
  r.identified = true;
}

/// The trim windows' means of each column, as a matrix (rows: windows).
Eigen::MatrixXd window_matrix(const Context& c, const std::vector<const Col*>& columns) {
  Eigen::MatrixXd X(static_cast<Eigen::Index>(c.L.windows.size()), static_cast<Eigen::Index>(columns.size()));
  for (std::size_t j = 0; j < columns.size(); ++j) {
    const Col m = window_means(*columns[j], c.L);
    for (std::size_t i = 0; i < m.size(); ++i) X(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = m[i];
  }
  return X;
}

/// The batch (segment piece) each trim window starts in; windows outside every piece: the last batch + 1.
std::vector<std::size_t> window_batches(const Layout& L) {
  std::vector<std::size_t> batch;
  for (const auto& w : L.windows) {
    std::size_t i = 0;
    while (i < L.segments.size() && !(w.front() >= L.segments[i].first && w.front() < L.segments[i].second)) ++i;
    batch.push_back(i);
  }
  return batch;
}

/// The delete-one-batch jackknife of a trim fit (batch_scatter's, over the windows of each batch):
/// what the flight's pieces, each at its own airspeeds, disagree by. Zero with fewer than three.
Eigen::VectorXd trim_jackknife(const Layout& L, const Eigen::MatrixXd& X, const Eigen::VectorXd& z, const Eigen::MatrixXd* Z) {
  const std::vector<std::size_t> batch = window_batches(L);
  std::vector<Eigen::VectorXd> thetas;
  for (std::size_t b = 0; b <= L.segments.size(); ++b) {
    std::vector<Eigen::Index> keep;
    for (std::size_t i = 0; i < batch.size(); ++i)
      if (batch[i] != b) keep.push_back(static_cast<Eigen::Index>(i));
    if (keep.size() == batch.size() || keep.size() <= 3 * static_cast<std::size_t>(X.cols())) continue;
    const Eigen::MatrixXd Xb = X(keep, Eigen::all), Zb = Z != nullptr ? Eigen::MatrixXd((*Z)(keep, Eigen::all)) : Xb;
    const Eigen::VectorXd zb = z(keep);
    if (std::abs((Zb.transpose() * Xb).determinant()) < 1e-12 * (Zb.norm() * Xb.norm())) continue;  // a batch held every airspeed
    thetas.push_back(least_squares(Xb, zb, 3, Z != nullptr ? &Zb : nullptr).theta);
  }
  return jackknife_se(thetas, X.cols());
}

/// Time-domain least squares on the trim windows' means: z = X theta, with `instruments` (one per
/// column, or empty: ordinary least squares) the instrumental-variable estimate; the bounds never
/// below the delete-one-batch jackknife's (trim_jackknife). Returns it.
LsEstimate trim_fit(Context& c, const Col& z, const std::vector<const Col*>& columns, const std::vector<const Col*>& instruments = {}) {
  const Col zm = window_means(z, c.L);
  const Eigen::MatrixXd X = window_matrix(c, columns);
  if (X.rows() <= X.cols()) throw std::runtime_error(fmt::format("too few trim windows ({}) of {} s", X.rows(), c.o.trim_window_s));
  const Eigen::MatrixXd Z = instruments.empty() ? X : window_matrix(c, instruments);
  const Eigen::Map<const Eigen::VectorXd> zz(zm.data(), static_cast<Eigen::Index>(zm.size()));
  const Eigen::MatrixXd* iv = instruments.empty() ? nullptr : &Z;
  LsEstimate e = least_squares(X, zz, 3, iv);
  e.std_error = e.std_error.cwiseMax(trim_jackknife(c.L, X, zz, iv));
  return e;
}

double stddev(const Col& x) {
  double m = 0.0;
  for (const double v : x) m += v;
  m /= static_cast<double>(x.size());
  double s = 0.0;
  for (const double v : x) s += (v - m) * (v - m);
  return std::sqrt(s / static_cast<double>(x.size()));
}

/// The excitation tests (identify.hpp), worded for the log.
struct Signals {
  Excitation alpha, beta, p, q, r, delta_a, delta_e, delta_r;
};

Signals signals(const AeroSamples& a, const Col& alpha, const Col& beta) {
  const double angle = 0.3 * kRadPerDeg, rate = 5.0 * kRadPerDeg;
  return {{&alpha, false, angle, "alpha never moved more than 0.3 deg about its trim"},
          {&beta, false, angle, "sideslip never moved more than 0.3 deg about its trim"},
          {&a.p, true, 2.0 * rate, "roll rate never above 10 deg/s"},
          {&a.q, true, rate, "pitch rate never above 5 deg/s"},
          {&a.r, true, rate, "yaw rate never above 5 deg/s"},
          {&a.delta_a, false, angle, "aileron never moved more than 0.3 deg about its trim"},
          {&a.delta_e, false, angle, "elevator never moved more than 0.3 deg about its trim"},
          {&a.delta_r, false, angle, "rudder never moved more than 0.3 deg about its trim"}};
}

/// The band's estimate of `name`, taken out of the result (reported, not adopted); nullopt if the
/// band did not identify it.
std::optional<CoefficientEstimate> take_out(Context& c, const std::string& name) {
  auto& all = c.result.coefficients;
  const auto it = std::find_if(all.begin(), all.end(), [&](const CoefficientEstimate& e) { return e.name == name; });
  std::optional<CoefficientEstimate> out;
  if (it == all.end()) return out;
  if (it->identified) out = *it;
  all.erase(it);
  return out;
}

/// What a model instrument stands for (sideslip_instrument.hpp): a flow angle, or a nondimensional
/// lateral rate.
enum class Modelled { alpha, beta, p_hat, r_hat };

/// The excitation's part of `command` (one of c.a's delta_*) where the log has one that moved
/// about its trim by more than the excitation test's 0.3 deg (throttle: 0.01); else nullptr. In a
/// closed-loop flight the controller's share of a command answers the gusts, which are the
/// regressions' error: only the excitation's share is independent of them (Soderstrom and Stoica,
/// *System Identification*, ch. 10: systems operating in closed loop).
const Col* excitation_part(const Context& c, const Col& command) {
  const AeroSamples& a = c.a;
  const std::tuple<const Col*, const Col*, double> parts[] = {{&a.delta_a, &a.exc_delta_a, 0.3 * kRadPerDeg},
                                                              {&a.delta_e, &a.exc_delta_e, 0.3 * kRadPerDeg},
                                                              {&a.delta_r, &a.exc_delta_r, 0.3 * kRadPerDeg},
                                                              {&a.delta_t, &a.exc_delta_t, 0.01}};
  for (const auto& [cmd, part, threshold] : parts)
    if (cmd == &command) return !part->empty() && rms(detrended(*part, c.L)) > threshold ? part : nullptr;
  return nullptr;
}

/// The instrument for alpha (the lift's), beta (the side force's) or p^ and r^ (the rolling and
/// yawing moments'), put into the spectra under `key` (sideslip_instrument.hpp): each stretch's
/// response of the linear model to its commands (elevator and throttle, or aileron and rudder),
/// linearised at the stretch's mean airspeed with the coefficients known so far. The model is
/// driven by the excitation's part of the commands where the log has it (excitation_part), by the
/// whole commands otherwise. False (no instrument) when that model does not trim, with the reason
/// in `why`.
bool put_model_instrument(Context& c, Modelled what, const Col& key, std::string& why) {
  const bool lateral = what != Modelled::alpha;
  const Col& u1 = lateral ? c.a.delta_a : c.a.delta_e;
  const Col& u2 = lateral ? c.a.delta_r : c.a.delta_t;
  const bool excited = excitation_part(c, u1) != nullptr || excitation_part(c, u2) != nullptr;
  const Col& x1 = excited ? (lateral ? c.a.exc_delta_a : c.a.exc_delta_e) : u1;
  const Col& x2 = excited ? (lateral ? c.a.exc_delta_r : c.a.exc_delta_t) : u2;
  const Eigen::VectorXcd& U1 = c.spectra.of(x1);
  const Eigen::VectorXcd& U2 = c.spectra.of(x2);
  Eigen::VectorXcd Z(U1.size());
  Aircraft model = c.result.aircraft;
  model.aero = c.coef;
  for (std::size_t i = 0; i < c.L.segments.size(); ++i) {
    const auto [b, e] = c.L.segments[i];
    double Va = 0.0;
    for (std::size_t k = b; k < e; ++k) Va += c.a.Va[k] / static_cast<double>(e - b);
    const auto [first, n] = c.spectra.segment_rows()[i];
    const Col f = c.spectra.segment_frequencies(i);
    try {
      const tern::aero::LinearModel m = tern::aero::linearize(model, {Va});
      const auto u1 = U1.segment(first, n), u2 = U2.segment(first, n);
      const double half_span = 0.5 * model.b;
      switch (what) {
        case Modelled::alpha: Z.segment(first, n) = modelled_alpha(m, f, u1, u2); break;
        case Modelled::beta: Z.segment(first, n) = modelled_sideslip(m, f, u1, u2); break;
        case Modelled::p_hat: Z.segment(first, n) = half_span * modelled_roll_rate(m, f, u1, u2); break;
        case Modelled::r_hat: Z.segment(first, n) = half_span * modelled_yaw_rate(m, f, u1, u2); break;
      }
    } catch (const std::exception& ex) {
      why = fmt::format("the linear model does not trim at {:.1f} m/s ({})", Va, ex.what());
      return false;
    }
  }
  c.spectra.put(&key, std::move(Z));
  return true;
}

/// C_L - C_L_q q^ - C_L_delta_e delta_e = C_L_0 + C_L_alpha alpha on the trim windows' means (the
/// two terms scaled by q_scale, delta_e_scale: the consider covariance's shifted fits).
LsEstimate lift_trim_fit(Context& c, double q_scale = 1.0, double delta_e_scale = 1.0) {
  const AeroSamples& a = c.a;
  Col z(a.size());
  for (std::size_t k = 0; k < a.size(); ++k)
    z[k] = a.C_L[k] - q_scale * c.coef.C_L_q * a.q_hat[k] - delta_e_scale * c.coef.C_L_delta_e * a.delta_e[k];
  const Col ones(a.size(), 1.0);
  // alpha's instrument: 1 / qbar (the trim's alpha at 1 g goes as m g / (qbar S)), whose error (the
  // pitot's noise, the longitudinal gust) is independent of the reconstructed alpha's (the vertical
  // gust): the window means of alpha carry that error undiminished by the flight's length, and
  // ordinary least squares on them flattens the lift curve
  Col inv_qbar(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) inv_qbar[k] = 1.0 / (a.Va[k] * a.Va[k]);
  return trim_fit(c, z, {&ones, &a.alpha}, {&ones, &inv_qbar});
}

/// The lift's trim fit with the bounds widened by what the kept pitch-rate and elevator terms'
/// uncertainty (kPriorUncertainty, or the band's standard error where identified) moves it by.
LsEstimate lift_trim_considered(Context& c) {
  LsEstimate e = lift_trim_fit(c);
  Eigen::VectorXd extra = Eigen::VectorXd::Zero(e.theta.size());
  for (const char* name : {"C_L_q", "C_L_delta_e"}) {
    double rel = kPriorUncertainty;
    for (const auto& r : c.result.coefficients)
      if (r.name == name && r.identified && r.estimate != 0.0) rel = r.std_error / std::abs(r.estimate);
    const bool q = std::string(name) == "C_L_q";
    const LsEstimate shifted = lift_trim_fit(c, q ? 1.0 + rel : 1.0, q ? 1.0 : 1.0 + rel);
    extra += (shifted.theta - e.theta).cwiseAbs2();
  }
  e.std_error = (e.std_error.cwiseAbs2() + extra).cwiseSqrt();
  return e;
}

/// The band's lift fit on the reconstructed alpha below which its terms are not taken.
constexpr double kMinLiftBandFit = 0.9;

/// The lift's pitch-rate and elevator terms back to the prior, with the reason.
void lift_band_rejected(Context& c, const std::string& why) {
  for (auto& e : c.result.coefficients)
    if ((e.name == "C_L_q" || e.name == "C_L_delta_e") && e.identified) {
      e.identified = false, e.estimate = e.prior, e.std_error = 0.0, e.note = why;
      c.coef.*(e.name == "C_L_q" ? &M::C_L_q : &M::C_L_delta_e) = e.prior;
    }
}

/// Lift. The pitch-rate and elevator terms in the band, beside the reconstructed alpha instrumented
/// by the longitudinal model's; C_L_0 and C_L_alpha from the trim windows' means by instrumental
/// variables (lift_trim_fit), with those terms. The band's own fit is the check: if alpha explains
/// less than kMinLiftBandFit of the lift in the band, or the band's C_L_alpha disagrees with the
/// trim's (beyond 3 of its standard errors and 5 %), the band's terms are not taken.
void lift(Context& c, const Excitation& alpha, const Excitation& q, const Excitation& delta_e) {
  const AeroSamples& a = c.a;
  // the reconstructed alpha misses the vertical gusts: instrumented by the longitudinal model's
  const Col alpha_model(a.size(), 0.0);  // a key: its spectrum is put in the frequency domain
  std::string why;
  const bool iv = put_model_instrument(c, Modelled::alpha, alpha_model, why);
  if (!iv) c.result.notes.push_back(fmt::format("lift: alpha not instrumented in the band: {}", why));
  band_fit(c, "lift", a.C_L,
           {{"C_L_alpha", &M::C_L_alpha, &a.alpha, alpha, iv ? &alpha_model : nullptr},
            {"C_L_q", &M::C_L_q, &a.q_hat, q},
            {"C_L_delta_e", &M::C_L_delta_e, &a.delta_e, delta_e}});
  c.spectra.forget(&alpha_model);
  const std::optional<CoefficientEstimate> band = take_out(c, "C_L_alpha");
  c.coef.C_L_alpha = c.prior.C_L_alpha;
  const Term t0{"C_L_0", &M::C_L_0, nullptr, {}}, ta{"C_L_alpha", &M::C_L_alpha, nullptr, {}};
  const double spread = stddev(window_means(a.alpha, c.L));
  if (spread < kRadPerDeg) {
    const std::string why = fmt::format("alpha's trim never spread beyond {:.2f} deg (fly several airspeeds)", spread * kDegPerRad);
    record(c, t0, "trim").note = why;
    record(c, ta, "trim").note = why;
    lift_band_rejected(c, "not checked: no trim C_L_alpha to hold the band's against");
    return;
  }
  LsEstimate e = lift_trim_considered(c);
  const auto fit = std::find_if(c.result.fits.begin(), c.result.fits.end(), [](const AxisFit& f) { return f.axis == "lift"; });
  if (fit != c.result.fits.end() && fit->r_squared < kMinLiftBandFit) {
    lift_band_rejected(c, fmt::format("the reconstructed alpha explains R^2 {:.2f} of the lift in the band (gusts the flight path misses)",
                                      fit->r_squared));
    e = lift_trim_considered(c);
  } else if (band && std::abs(band->estimate - e.theta[1]) > std::max(3.0 * band->std_error, 0.05 * std::abs(e.theta[1]))) {
    lift_band_rejected(
        c, fmt::format("the reconstructed alpha disagrees with the lift (C_L_alpha {:.3g} +- {:.2g} in the band, {:.3g} from the trim): "
                       "gusts the flight path misses",
                       band->estimate, band->std_error, e.theta[1]));
    e = lift_trim_considered(c);
  }
  c.coef.C_L_0 = e.theta[0], c.coef.C_L_alpha = e.theta[1];
  c.result.fits.push_back({"lift", "trim", e.r_squared, std::sqrt(e.s2), e.rows});
  for (int j = 0; j < 2; ++j) {
    CoefficientEstimate& r = record(c, j == 0 ? t0 : ta, "trim");
    r.std_error = e.std_error[j];
    r.identified = true;
  }
}

/// alpha where the accelerometers' lift says it was (identify.hpp, step 2). The lift is the body
/// force turned through alpha itself: the estimator's first, then twice the lift's own.
Col alpha_from_lift(const Context& c) {
  const AeroSamples& a = c.a;
  Col alpha = a.alpha;
  for (int pass = 0; pass < 3; ++pass)
    for (std::size_t k = 0; k < a.size(); ++k) {
      const double C_L = std::sin(alpha[k]) * a.C_X[k] - std::cos(alpha[k]) * a.C_Z[k];
      alpha[k] = (C_L - c.coef.C_L_0 - c.coef.C_L_q * a.q_hat[k] - c.coef.C_L_delta_e * a.delta_e[k]) / c.coef.C_L_alpha;
    }
  return alpha;
}

/// The drag coefficient with the body forces turned through `alpha`.
Col drag_at(const AeroSamples& a, const Col& alpha) {
  Col C_D(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) C_D[k] = -(std::cos(alpha[k]) * a.C_X[k] + std::sin(alpha[k]) * a.C_Z[k]);
  return C_D;
}

/// The polar's trim windows (instrumentation.hpp): C_D - C_D_q q^ - C_D_delta_e delta_e, C_Lw =
/// C_L_scale (C_L_0 + C_L_alpha alpha) (sim_aero's drag_coefficient in the linear range) and the
/// accelerometer bias's regressor -m cos(alpha) / (qbar_xz S), each a window's mean.
std::vector<PolarWindow> polar_windows(const Context& c, const AeroSamples& a, const Col& alpha, const Aircraft& ac, double C_L_scale) {
  const Col C_D = drag_at(a, alpha);
  Col z(a.size()), clw(a.size()), bias(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    z[k] = C_D[k] - c.coef.C_D_q * a.q_hat[k] - c.coef.C_D_delta_e * a.delta_e[k];
    clw[k] = C_L_scale * (c.coef.C_L_0 + c.coef.C_L_alpha * alpha[k]);
    const double V_xz = a.Va[k] * std::cos(a.beta[k]);
    bias[k] = -ac.mass * std::cos(alpha[k]) / (0.5 * ac.rho * V_xz * V_xz * ac.S);
  }
  const Col zm = window_means(z, c.L), cm = window_means(clw, c.L), bm = window_means(bias, c.L);
  std::vector<PolarWindow> w(zm.size());
  for (std::size_t i = 0; i < zm.size(); ++i) w[i] = {zm[i], cm[i], bm[i]};
  return w;
}

/// sigma widened by what `shifted` moved the estimate by (a consider term: the pitot scale's).
void widen(NuisanceEstimate& e, const NuisanceEstimate& shifted) {
  if (e.identified && shifted.identified) e.std_error = std::hypot(e.std_error, shifted.estimate - e.estimate);
}

/// The polar and the accelerometer's x bias from the trim (instrumentation.hpp). `at_k_plus_sigma`:
/// the samples with the pitot scale one standard error higher (nullptr when k was not identified),
/// whose shift of every estimate is added to its standard error; the lift then scales by
/// (k / (k + sigma))^2 (`C_L_scale`).
void drag(Context& c, const Col& alpha, const Aircraft& prior, const AeroSamples* at_k_plus_sigma, double C_L_scale) {
  DragPolar p = drag_polar(polar_windows(c, c.a, alpha, prior, 1.0), prior.AR(), c.o.max_relative_error, 3, c.o.fit_accel_x_bias);
  if (at_k_plus_sigma != nullptr) {
    const DragPolar q = drag_polar(polar_windows(c, *at_k_plus_sigma, alpha, prior, C_L_scale), prior.AR(), c.o.max_relative_error, 3,
                                   c.o.fit_accel_x_bias);
    widen(p.C_D_p, q.C_D_p), widen(p.K, q.K), widen(p.e, q.e), widen(p.bias_x, q.bias_x);
  }
  c.result.fits.push_back({"drag", "trim", p.r_squared, p.rms_residual, p.rows});
  c.coef.C_D_p = p.C_D_p.estimate;
  const Term tp{"C_D_p", &AeroCoefficients::C_D_p, nullptr, {}};
  CoefficientEstimate& r = record(c, tp, "trim");
  r.std_error = p.C_D_p.std_error;
  r.identified = true;
  const double prior_e = c.result.aircraft.e;
  if (p.e.identified) {
    c.result.aircraft.e = p.e.estimate;
    c.result.notes.push_back(fmt::format("e (Oswald factor): {:.3f} +- {:.2g} (prior {:.3f}), from the polar's slope {:.4f} +- {:.2g}",
                                         p.e.estimate, p.e.std_error, prior_e, p.K.estimate, p.K.std_error));
  } else {
    c.result.notes.push_back(fmt::format("e (Oswald factor): kept, {}", p.K.note));
  }
  c.result.oswald = p.e;
  c.result.accel_x_bias = p.bias_x;
  if (!p.bias_x.identified) c.result.notes.push_back(fmt::format("accelerometer x bias: {}; 0 taken", p.bias_x.note));
  for (const Term& t :
       {Term{"C_D_q", &AeroCoefficients::C_D_q, nullptr, {}}, Term{"C_D_delta_e", &AeroCoefficients::C_D_delta_e, nullptr, {}}})
    record(c, t, "trim").note = "kept: small beside the polar's terms at trim";
}

/// The instruments of the lateral rates in a closed-loop flight: the lateral model's p^ and r^ for
/// the excitation (put_model_instrument), or none.
struct RateInstruments {
  const Col* p_hat = nullptr;
  const Col* r_hat = nullptr;
};

/// The lateral terms of one axis (C_Y, C_ell or C_n: members in the order beta, p, r, delta_a, delta_r);
/// with `closed_loop`, each command instrumented by its excitation's part where it has one, and the
/// rates by `rates`.
std::vector<Term> lateral_terms(const Context& c, const std::string& axis, const std::array<Member, 5>& m, const Col& beta,
                                const Signals& x, const Col* beta_instrument = nullptr, bool closed_loop = false,
                                RateInstruments rates = {}) {
  const AeroSamples& a = c.a;
  const Col* da = closed_loop ? excitation_part(c, a.delta_a) : nullptr;
  const Col* dr = closed_loop ? excitation_part(c, a.delta_r) : nullptr;
  return {{axis + "_beta", m[0], &beta, x.beta, beta_instrument},
          {axis + "_p", m[1], &a.p_hat, x.p, rates.p_hat},
          {axis + "_r", m[2], &a.r_hat, x.r, rates.r_hat},
          {axis + "_delta_a", m[3], &a.delta_a, x.delta_a, da},
          {axis + "_delta_r", m[4], &a.delta_r, x.delta_r, dr}};
}

/// beta where the side force says it was, once C_Y is known (identify.hpp, step 2); with
/// `from_force` false, the estimator's.
Col beta_from_side_force(const Context& c, bool from_force) {
  const AeroSamples& a = c.a;
  if (!from_force) return a.beta;
  const M& m = c.coef;
  Col beta(a.size());
  for (std::size_t k = 0; k < a.size(); ++k)
    beta[k] =
        (a.C_Y[k] - m.C_Y_0 - m.C_Y_p * a.p_hat[k] - m.C_Y_r * a.r_hat[k] - m.C_Y_delta_a * a.delta_a[k] - m.C_Y_delta_r * a.delta_r[k]) /
        m.C_Y_beta;
  return beta;
}

void drag_at_trim(SysidResult& r, const Aircraft& prior, const Col& alpha, const AeroSamples& a) {
  double al = 0.0, de = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) al += alpha[k], de += a.delta_e[k];
  al /= static_cast<double>(a.size()), de /= static_cast<double>(a.size());
  r.C_D_trim_prior = sim::drag_coefficient(prior, al) + prior.aero.C_D_delta_e * de;
  r.C_D_trim = sim::drag_coefficient(r.aircraft, al) + r.aircraft.aero.C_D_delta_e * de;
  const double C_L = sim::lift_coefficient(r.aircraft, al) + r.aircraft.aero.C_L_delta_e * de;
  r.C_D_per_deg = C_L * kRadPerDeg / r.C_D_trim;
}

/// The lift's alpha carries the lift's pitch-rate and elevator terms: alpha = (C_L - C_L_0 - C_L_q q^
/// - C_L_delta_e delta_e) / C_L_alpha, so the pitching moment's fit takes C_m_q as b + (C_m_alpha /
/// C_L_alpha) C_L_q and C_m_delta_e likewise. Where those lift terms kept their prior, the prior's
/// uncertainty (kPriorUncertainty) is added to C_m_q's and C_m_delta_e's bounds (a consider
/// covariance).
void consider_lift_terms(Context& c) {
  const double ratio = std::abs(c.coef.C_m_alpha / c.coef.C_L_alpha);
  const std::pair<const char*, const char*> pairs[] = {{"C_m_q", "C_L_q"}, {"C_m_delta_e", "C_L_delta_e"}};
  for (const auto& [moment, lift] : pairs) {
    const auto find = [&](const char* name) {
      return std::find_if(c.result.coefficients.begin(), c.result.coefficients.end(),
                          [&](const CoefficientEstimate& e) { return e.name == name; });
    };
    const auto m = find(moment), l = find(lift);
    if (m == c.result.coefficients.end() || l == c.result.coefficients.end() || !m->identified || l->identified) continue;
    const double consider = ratio * kPriorUncertainty * std::abs(l->prior);
    m->std_error = std::hypot(m->std_error, consider);
  }
}

/// The pitching moment in the band, alpha from the lift instrumented by the reconstruction's (step 3).
void pitching_moment(Context& c, const Col& alpha, bool accel) {
  const AeroSamples& a = c.a;
  const Signals x = signals(a, alpha, a.beta);
  const std::vector<Term> pitch = {{"C_m_alpha", &M::C_m_alpha, &alpha, x.alpha, accel ? &a.alpha : nullptr},
                                   {"C_m_q", &M::C_m_q, &a.q_hat, x.q},
                                   {"C_m_delta_e", &M::C_m_delta_e, &a.delta_e, x.delta_e}};
  band_fit(c, "pitch", a.C_m, pitch);
  bias_fit(c, "C_m_0", &M::C_m_0, a.C_m, pitch);
}

/// The lateral axes (steps 2-3): the side force with beta instrumented by the lateral model's
/// sideslip (the model of c.coef as it stands: the prior's lateral coefficients), beta from the side
/// force, then the rolling and yawing moments with it (instrumented by the reconstruction's).
/// Returns that beta. (A second pass with the instrument from the first pass's coefficients, the
/// iterated instrument, moved C_Y_beta by 1-4 % on seeds 1, 2 and 4 of the bench, not toward the
/// truth on all: not taken.)
Col lateral(Context& c, const Col& alpha, bool accel) {
  const AeroSamples& a = c.a;
  const Col beta_model(a.size(), 0.0);  // a key: its spectrum is put in the frequency domain
  std::string why;
  const bool side_iv = put_model_instrument(c, Modelled::beta, beta_model, why);
  if (!side_iv) c.result.notes.push_back(fmt::format("side force: beta not instrumented: {}", why));
  Signals x = signals(a, alpha, a.beta);
  std::vector<Term> side = lateral_terms(c, "C_Y", {&M::C_Y_beta, &M::C_Y_p, &M::C_Y_r, &M::C_Y_delta_a, &M::C_Y_delta_r}, a.beta, x,
                                         side_iv ? &beta_model : nullptr, side_iv);
  if (side_iv)  // the model's sideslip is itself a mix of the rates' responses: beside it p^ and r^ take up its error
    for (Term& t : side)
      if (t.name == "C_Y_p" || t.name == "C_Y_r")
        t.excitation = {t.excitation.signal, true, std::numeric_limits<double>::infinity(),
                        "held: the instrumented sideslip leaves the side force's rate terms undetermined (small on a symmetric airframe)"};
  band_fit(c, "side force", a.C_Y, side);
  c.spectra.forget(&beta_model);
  bias_fit(c, "C_Y_0", &M::C_Y_0, a.C_Y, side);
  Col beta = beta_from_side_force(c, accel);
  x = signals(a, alpha, beta);
  const Col* beta_iv = accel ? &a.beta : nullptr;
  // In closed loop the rates answer the sensors' noise through the controller, as the commands do
  // (the yaw damper feeds r straight back to the rudder): in the yawing moment they and the commands
  // are instrumented by the lateral model's response to the excitation. The rolling moment keeps its
  // own: its signal is some five times larger beside the same noise, and there those instruments
  // cost more precision than they remove bias (bench seeds 1-5: C_ell_delta_a 5 -> 12 %).
  const Col p_model(a.size(), 0.0), r_model(a.size(), 0.0);  // keys: their spectra are put in the frequency domain
  const bool closed = excitation_part(c, a.delta_a) != nullptr || excitation_part(c, a.delta_r) != nullptr;
  const bool rates_iv =
      closed && put_model_instrument(c, Modelled::p_hat, p_model, why) && put_model_instrument(c, Modelled::r_hat, r_model, why);
  if (closed && !rates_iv) c.result.notes.push_back(fmt::format("yaw: the rates not instrumented: {}", why));
  const RateInstruments rates = rates_iv ? RateInstruments{&p_model, &r_model} : RateInstruments{};
  const std::vector<Term> roll =
      lateral_terms(c, "C_ell", {&M::C_ell_beta, &M::C_ell_p, &M::C_ell_r, &M::C_ell_delta_a, &M::C_ell_delta_r}, beta, x, beta_iv);
  band_fit(c, "roll", a.C_ell, roll);
  bias_fit(c, "C_ell_0", &M::C_ell_0, a.C_ell, roll);
  const std::vector<Term> yaw =
      lateral_terms(c, "C_n", {&M::C_n_beta, &M::C_n_p, &M::C_n_r, &M::C_n_delta_a, &M::C_n_delta_r}, beta, x, beta_iv, rates_iv, rates);
  band_fit(c, "yaw", a.C_n, yaw);
  bias_fit(c, "C_n_0", &M::C_n_0, a.C_n, yaw);
  c.spectra.forget(&p_model);
  c.spectra.forget(&r_model);
  return beta;
}

/// The output-error refinement (output_error.hpp) of one group of axes: the coefficients of the
/// axes' moments the equation error identified, from their estimates; the others held.
void refine(Context& c, const RateData& d, RateAxes axes) {
  std::vector<std::string> free;
  for (const auto& e : c.result.coefficients) {
    const bool pitch = e.name.rfind("C_m_", 0) == 0, lateral = e.name.rfind("C_ell_", 0) == 0 || e.name.rfind("C_n_", 0) == 0;
    if (e.identified && (axes == RateAxes::pitch ? pitch : lateral)) free.push_back(e.name);
  }
  if (free.empty()) return;
  const OutputErrorFit f = output_error(d, c.result.aircraft, c.coef, axes, free, c.o.output_error);
  const std::vector<std::string> outputs =
      axes == RateAxes::pitch ? std::vector<std::string>{"pitch rate"} : std::vector<std::string>{"roll rate", "yaw rate"};
  std::string rms;
  for (std::size_t a = 0; a < outputs.size(); ++a) {
    const auto A = static_cast<Eigen::Index>(a);
    c.result.fits.push_back({outputs[a], "output error", f.r_squared[A], f.rms[A], f.samples});
    rms += fmt::format("{}{} {:.4f} -> {:.4f} rad/s", a ? ", " : "", outputs[a], f.rms_start[A], f.rms[A]);
  }
  c.result.notes.push_back(fmt::format("output error ({}): {} coefficients, residual rms {}; {} relaxations, {} simulations",
                                       axes == RateAxes::pitch ? "pitch" : "roll and yaw", free.size(), rms, f.relaxations, f.evaluations));
  for (std::size_t j = 0; j < free.size(); ++j) {
    const auto J = static_cast<Eigen::Index>(j);
    auto e = std::find_if(c.result.coefficients.begin(), c.result.coefficients.end(),
                          [&](const CoefficientEstimate& x) { return x.name == free[j]; });
    double se = f.std_error[J];
    if (se > c.o.max_relative_error * std::abs(f.theta[J])) {
      c.result.notes.push_back(fmt::format("{}: output error poorly determined ({:.4g} +- {:.2g}); the equation error's {:.4g} kept",
                                           e->name, f.theta[J], se, e->estimate));
      continue;
    }
    // the output error further from the equation error than its own bound: one of them is biased
    // (the equation error by its flow angles' errors; the output error by the turbulence it does not
    // model, process noise, and by the noise in the flow angles it is driven by: Klein and Morelli
    // ch. 6), and which is not known. The estimate is then their mean, its bound the larger of
    // theirs and half the gap (the truth between them lies inside it).
    double theta = f.theta[J];
    std::string method = "output error";
    const double apart = std::abs(f.theta[J] - e->estimate);
    if (apart > se) {
      se = std::max({se, e->std_error, 0.5 * apart});
      theta = 0.5 * (f.theta[J] + e->estimate);
      method = "mean of equation and output error";
    }
    e->estimate = theta, e->std_error = se, e->method = method;
    c.coef.*moment_coefficient(e->name) = theta;
  }
}

/// The gyros' roll-yaw coupling as a consider covariance. A yaw gyro that reads r + kappa p puts
/// kappa Jz p' into the measured yawing moment; p' is the rolling moment over Jx, so every C_n_x
/// comes out as C_n_x + kappa (Jz / Jx) C_ell_x, whatever the method: the model explains the
/// contamination with its own terms, and nothing in the moments tells the two apart (likewise
/// C_ell_x by kappa (Jx / Jz) C_n_x). With |kappa| up to o.gyro_cross_axis that shift is added
/// to each identified coefficient's bound. (On the bench's seed 4, flown with the realistic IMU's
/// cross-axis sensitivity and misalignment switched off, C_n_r's error went from 20 % to 5 %.)
void consider_gyro_coupling(Context& c) {
  const AeroCoefficients& m = c.coef;
  const Aircraft& ac = c.result.aircraft;
  const std::array<std::tuple<const char*, double, const char*, double>, 5> pairs = {
      {{"C_ell_beta", m.C_ell_beta, "C_n_beta", m.C_n_beta},
       {"C_ell_p", m.C_ell_p, "C_n_p", m.C_n_p},
       {"C_ell_r", m.C_ell_r, "C_n_r", m.C_n_r},
       {"C_ell_delta_a", m.C_ell_delta_a, "C_n_delta_a", m.C_n_delta_a},
       {"C_ell_delta_r", m.C_ell_delta_r, "C_n_delta_r", m.C_n_delta_r}}};
  const double k = c.o.gyro_cross_axis;
  for (CoefficientEstimate& e : c.result.coefficients) {
    if (!e.identified) continue;
    for (const auto& [roll, C_ell, yaw, C_n] : pairs) {
      if (e.name == yaw) e.std_error = std::hypot(e.std_error, k * (ac.Jz / ac.Jx) * C_ell);
      if (e.name == roll) e.std_error = std::hypot(e.std_error, k * (ac.Jx / ac.Jz) * C_n);
    }
  }
}

/// Each axis's measured and predicted coefficient over the longest stretch.
std::vector<AxisSeries> axis_series(const AeroSamples& a, const Layout& L, const AeroCoefficients& m, const Aircraft& ac, const Col& alpha,
                                    const Col& beta) {
  std::pair<std::size_t, std::size_t> longest = L.segments.front();
  for (const auto& s : L.segments)
    if (s.second - s.first > longest.second - longest.first) longest = s;
  std::vector<AxisSeries> out;
  for (const char* axis : {"C_L", "C_D", "C_Y", "C_ell", "C_m", "C_n"}) out.push_back({axis, {}, {}, {}});
  for (std::size_t k = longest.first; k < longest.second; ++k) {
    const double al = alpha[k], be = beta[k], ph = a.p_hat[k], qh = a.q_hat[k], rh = a.r_hat[k];
    const double da = a.delta_a[k], de = a.delta_e[k], dr = a.delta_r[k];
    const double predicted[6] = {
        m.C_L_0 + m.C_L_alpha * al + m.C_L_q * qh + m.C_L_delta_e * de,
        sim::drag_coefficient(ac, al) + m.C_D_q * qh + m.C_D_delta_e * de,
        m.C_Y_0 + m.C_Y_beta * be + m.C_Y_p * ph + m.C_Y_r * rh + m.C_Y_delta_a * da + m.C_Y_delta_r * dr,
        m.C_ell_0 + m.C_ell_beta * be + m.C_ell_p * ph + m.C_ell_r * rh + m.C_ell_delta_a * da + m.C_ell_delta_r * dr,
        m.C_m_0 + m.C_m_alpha * al + m.C_m_q * qh + m.C_m_delta_e * de,
        m.C_n_0 + m.C_n_beta * be + m.C_n_p * ph + m.C_n_r * rh + m.C_n_delta_a * da + m.C_n_delta_r * dr};
    const double measured[6] = {a.C_L[k], a.C_D[k], a.C_Y[k], a.C_ell[k], a.C_m[k], a.C_n[k]};
    for (std::size_t i = 0; i < 6; ++i) {
      out[i].t.push_back(a.t[k]);
      out[i].measured.push_back(measured[i]);
      out[i].predicted.push_back(predicted[i]);
    }
  }
  return out;
}

}  // namespace

SysidResult identify(const FlightSeries& series, const Aircraft& prior, const SysidOptions& o) {
  if (aero_samples(series, prior, o.airborne).size() < 2)
    throw std::runtime_error(
        fmt::format("no airborne samples (airborne: {}; then Va above {:g} of its median, |alpha|, |beta| below {:g} rad)",
                    airborne_mask(series, o.airborne.ground).rule, o.airborne.min_Va_ratio, o.airborne.max_flow_angle));
  const AirspeedScale scale = airspeed_scale(series, aero_samples(series, prior, o.airborne).source, prior.rho, o.max_correlation);
  const double k = scale.k.identified ? scale.k.estimate : 1.0;
  const AeroSamples a = aero_samples(series, prior, o.airborne, k);
  const Layout L = layout_of(a, o.trim_window_s, o.min_segment_s);
  if (L.segments.empty())
    throw std::runtime_error(
        fmt::format("no airborne stretch of {} s or more (the longest flight without a gap is shorter)", o.min_segment_s));
  {
    const Signals x = signals(a, a.alpha, a.beta);
    auto moved = [&](const Excitation& e) { return rms(detrended(*e.signal, L)) > e.threshold; };
    if (!moved(x.delta_a) && !moved(x.delta_e) && !moved(x.delta_r))
      throw std::runtime_error(
          "no excitation: aileron, elevator and rudder never moved more than 0.3 deg about their trim (fly configs/missions/sysid.yaml, "
          "docs/system-identification.md)");
  }
  SysidResult r;
  r.notes = series.notes;
  r.aircraft = prior;
  r.pitot_scale = scale.k;
  r.wind_n = scale.w_n, r.wind_e = scale.w_e;
  if (!scale.k.identified) r.notes.push_back(fmt::format("pitot scale: not identifiable: {}; 1 taken", scale.k.note));
  r.samples = a.size(), r.segments = L.segments.size();
  for (const auto& [b, e] : L.segments) r.airborne_s += a.t[e - 1] - a.t[b];
  AeroCoefficients coef = prior.aero;
  Context c{a, L, o, Spectra(a, L, o.band_lo_hz, o.band_hi_hz), coef, prior.aero, r};
  const Signals x0 = signals(a, a.alpha, a.beta);
  lift(c, x0.alpha, x0.q, x0.delta_e);
  const bool accel = o.flow_angles == FlowAngles::accelerometer;
  const Col alpha = accel ? alpha_from_lift(c) : a.alpha;
  if (scale.k.identified) {
    const double k_hi = k + scale.k.std_error;
    const AeroSamples a_hi = aero_samples(series, prior, o.airborne, k_hi);
    drag(c, alpha, prior, &a_hi, (k / k_hi) * (k / k_hi));
  } else {
    drag(c, alpha, prior, nullptr, 1.0);
  }
  pitching_moment(c, alpha, accel);
  const Col beta = lateral(c, alpha, accel);
  for (auto& e : r.coefficients) e.equation_error = e.estimate, e.equation_error_std_error = e.std_error;
  if (o.output_error.enabled) {
    const RateData d = rate_data(a, alpha, beta, L.segments, prior, o.output_error.window_s);
    refine(c, d, RateAxes::pitch);
    refine(c, d, RateAxes::lateral);
  }
  if (accel) consider_lift_terms(c);
  consider_gyro_coupling(c);
  r.aircraft.aero = coef;
  drag_at_trim(r, prior, alpha, a);
  r.series = axis_series(a, L, coef, r.aircraft, alpha, beta);
  for (const auto& e : r.coefficients)
    if (!e.identified) r.notes.push_back(fmt::format("{}: not identifiable: {}; the prior {:.4g} kept", e.name, e.note, e.prior));
  return r;
}

}  // namespace tern::core::sysid
