// The World Magnetic Model on GeographicLib (see tern/magnetic_model.hpp). The field is what
// GeographicLib::MagneticModel computes for a .wmm model (its MagneticModel.cpp: Field and
// FieldGeocentric): B = -a grad V with V the Schmidt semi-normalised sum of (g + t gdot, h + t hdot)
// at t years from the epoch, in geocentric X, Y, Z, rotated into the local east, north, up axes
// by Geocentric's matrix M (local = M^T geocentric). The coefficients are the build's transcription
// of data/magnetic/*.COF (world_magnetic_models.hpp).
#include "tern/magnetic_model.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/SphericalHarmonic1.hpp>
#include <fmt/format.h>

#include "world_magnetic_models.hpp"

namespace tern {
namespace {

constexpr double kWmmRadius = 6371200.0;  // m: the WMM's reference radius (NOAA's WMM report)
constexpr double kSpanYears = 5.0;        // each WMM is valid for five years from its epoch
constexpr double kMinHeight = -1000.0;    // m: the WMM's valid heights (NOAA: -1 km to 850 km)
constexpr double kMaxHeight = 850000.0;

/// One model ready to evaluate. SphericalHarmonic1 keeps iterators into the vectors: a Model is
/// built in place and never moved.
struct Model {
  explicit Model(const wmm::CofModel& cof);
  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;
  std::string name;
  double epoch;
  std::vector<double> C, S, C1, S1;  // GeographicLib's layout: column-major in m, S without m = 0
  GeographicLib::SphericalHarmonic1 sum;
};

// GeographicLib's index of (n, m) for degree N: m N - m (m - 1) / 2 + n; S omits the N + 1 m = 0
// terms (SphericalEngine::coeff::index).
int coefficient_index(int N, int n, int m) { return m * N - m * (m - 1) / 2 + n; }

Model::Model(const wmm::CofModel& cof) : name(cof.name), epoch(cof.epoch) {
  const int N = cof.rows[cof.row_count - 1].n;
  const std::size_t size = static_cast<std::size_t>((N + 1) * (N + 2) / 2);
  C.assign(size, 0.0);
  C1.assign(size, 0.0);
  S.assign(size - static_cast<std::size_t>(N + 1), 0.0);
  S1.assign(S.size(), 0.0);
  for (std::size_t i = 0; i < cof.row_count; ++i) {
    const wmm::CofRow& r = cof.rows[i];
    const int k = coefficient_index(N, r.n, r.m);
    C[k] = r.g;
    C1[k] = r.gdot;
    if (r.m > 0) {
      S[k - (N + 1)] = r.h;
      S1[k - (N + 1)] = r.hdot;
    }
  }
  sum = GeographicLib::SphericalHarmonic1(C, S, N, C1, S1, N, kWmmRadius, GeographicLib::SphericalHarmonic1::SCHMIDT);
}

/// Every shipped model, oldest epoch first (built once, on first use).
const std::vector<std::unique_ptr<Model>>& models() {
  static const std::vector<std::unique_ptr<Model>> all = [] {
    std::vector<std::unique_ptr<Model>> v;
    for (std::size_t i = 0; i < wmm::kModelCount; ++i) v.push_back(std::make_unique<Model>(wmm::kModels[i]));
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a->epoch < b->epoch; });
    return v;
  }();
  return all;
}

/// The newest model whose epoch is not after t (the oldest before them all), and whether t is
/// outside its span [epoch, epoch + 5].
const Model& model_for(double t, bool& extrapolated) {
  const auto& all = models();
  const Model* chosen = all.front().get();
  for (const auto& m : all)
    if (m->epoch <= t) chosen = m.get();
  extrapolated = t < chosen->epoch || t > chosen->epoch + kSpanYears;
  return *chosen;
}

void check_position(double lat_deg, double lon_deg, double height_m, double year) {
  if (!std::isfinite(lat_deg) || lat_deg < -90.0 || lat_deg > 90.0)
    throw std::invalid_argument(fmt::format("world_magnetic_field: latitude {} deg is outside [-90, 90]", lat_deg));
  if (!std::isfinite(lon_deg)) throw std::invalid_argument(fmt::format("world_magnetic_field: longitude {} deg is not finite", lon_deg));
  if (!(height_m >= kMinHeight && height_m <= kMaxHeight))
    throw std::invalid_argument(fmt::format("world_magnetic_field: height {} m is outside the WMM's [{}, {}] m above the ellipsoid",
                                            height_m, kMinHeight, kMaxHeight));
  if (!std::isfinite(year)) throw std::invalid_argument(fmt::format("world_magnetic_field: decimal year {} is not finite", year));
}

/// The field of one model at t (its own span or not).
MagneticField evaluate(const Model& model, double lat_deg, double lon_deg, double height_m, double year) {
  MagneticField f;
  f.model = model.name;
  f.extrapolated = year < model.epoch || year > model.epoch + kSpanYears;
  double X = 0, Y = 0, Z = 0;
  std::vector<double> M(9);  // Geocentric's rotation, row-major: geocentric = M local (ENU)
  GeographicLib::Geocentric::WGS84().Forward(lat_deg, lon_deg, height_m, X, Y, Z, M);
  double gx = 0, gy = 0, gz = 0;
  model.sum(year - model.epoch, X, Y, Z, gx, gy, gz);
  const double BX = -kWmmRadius * gx, BY = -kWmmRadius * gy, BZ = -kWmmRadius * gz;  // nT, geocentric
  const double east = M[0] * BX + M[3] * BY + M[6] * BZ;
  const double north = M[1] * BX + M[4] * BY + M[7] * BZ;
  const double up = M[2] * BX + M[5] * BY + M[8] * BZ;
  f.ned = Eigen::Vector3d(north, east, -up) * 1e-9;
  f.declination = std::atan2(f.ned.y(), f.ned.x());
  f.inclination = std::atan2(f.ned.z(), f.ned.head<2>().norm());
  f.intensity = f.ned.norm();
  return f;
}

}  // namespace

MagneticField world_magnetic_field(double lat_deg, double lon_deg, double height_m, double year) {
  check_position(lat_deg, lon_deg, height_m, year);
  bool extrapolated = false;
  return evaluate(model_for(year, extrapolated), lat_deg, lon_deg, height_m, year);
}

std::vector<MagneticModelInfo> world_magnetic_models() {
  std::vector<MagneticModelInfo> out;
  for (const auto& m : models()) out.push_back({m->name, m->epoch});
  return out;
}

MagneticField world_magnetic_field(double lat_deg, double lon_deg, double height_m, double year, std::string_view name) {
  check_position(lat_deg, lon_deg, height_m, year);
  std::string known;
  for (const auto& m : models()) {
    if (m->name == name) return evaluate(*m, lat_deg, lon_deg, height_m, year);
    known += (known.empty() ? "" : ", ") + m->name;
  }
  throw std::invalid_argument(fmt::format("world_magnetic_field: no model '{}' (shipped: {})", name, known));
}

}  // namespace tern
