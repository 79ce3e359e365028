// tern/magnetic_model.hpp: the Earth's main magnetic field from the World Magnetic Model (WMM), at
// a WGS-84 position and a date, as PX4 and ArduPilot look up declination, inclination and
// intensity.
//
// Source: the WMM coefficients of NOAA/NCEI and the British Geological Survey (public domain),
// shipped in data/magnetic/*.COF (WMM2015v2, WMM2020, WMM2025; data/magnetic/README.md gives
// their provenance) and compiled into libtern_sdk.so at build time: nothing is read at run time.
// The sum is GeographicLib's (SphericalHarmonic1, Schmidt semi-normalised, reference radius
// 6371200 m; Geocentric for the WGS-84 geodetic -> geocentric conversion and the local rotation),
// the evaluation GeographicLib::MagneticModel does for a .wmm model.
//
// Frames and units: latitude and longitude in degrees (WGS-84, north and east positive), height in
// m ABOVE THE WGS-84 ELLIPSOID (the WMM's height; an MSL altitude differs by the geoid's undulation,
// -17 m at Provo: 0.4 nT of the field's ~50000 nT). The field is in NED (north, east, down), tesla;
// declination east of true north positive, inclination below the horizontal positive, radians.
// Dates are decimal years (NOAA's convention: year + (day of the year - 1) / days in the year).
//
// The model is chosen by date: the one whose 5-year span [epoch, epoch + 5] holds it (at a shared
// boundary the newer one); before the oldest epoch the oldest, after the newest span the newest,
// both flagged `extrapolated` (the WMM is not valid there: its secular variation is a straight line).
//
// Errors: std::invalid_argument, one line naming the value: a non-finite input, a latitude outside
// [-90, 90], a height outside the WMM's [-1 km, 850 km], an invalid calendar date or ISO text.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "tern/export.hpp"

namespace tern {

/// The Earth's main field at one place and date.
struct MagneticField {
  Eigen::Vector3d ned = Eigen::Vector3d::Zero();  ///< field, NED, T
  double declination = 0.0;                       ///< rad, east of true north positive, (-pi, pi]
  double inclination = 0.0;                       ///< rad, below the horizontal positive, [-pi/2, pi/2]
  double intensity = 0.0;                         ///< total intensity |ned|, T
  std::string model;                              ///< the model used, as its file names it, e.g. "WMM-2025"
  bool extrapolated = false;                      ///< the date is outside that model's 5-year span
};

/// The WMM's field at latitude, longitude (deg, WGS-84), height above the ellipsoid (m) on a
/// decimal year (e.g. decimal_year(2025, 7, 1)). Throws std::invalid_argument for bad input.
TERN_API MagneticField world_magnetic_field(double lat_deg, double lon_deg, double height_m, double decimal_year);

/// One shipped model: its name as its file names it ("WMM-2015v2") and its epoch (decimal year).
struct MagneticModelInfo {
  std::string name;
  double epoch = 0.0;
};

/// The shipped models, oldest epoch first.
TERN_API std::vector<MagneticModelInfo> world_magnetic_models();

/// The field of the named model (one of world_magnetic_models()) on any decimal year, flagged
/// `extrapolated` outside its span: e.g. a model carried to its successor's epoch, whose field
/// there shows how far its secular variation strayed. Throws std::invalid_argument for bad input
/// or an unknown model, naming the shipped ones.
TERN_API MagneticField world_magnetic_field(double lat_deg, double lon_deg, double height_m, double decimal_year, std::string_view model);

/// A calendar date (Gregorian).
struct CalendarDate {
  int year = 0, month = 0, day = 0;
};

/// The decimal year of a Gregorian date at 00:00 UTC: year + (day of the year - 1) / (365 or 366),
/// as NOAA's WMM software counts it (2025-07-01 -> 2025 + 181/365 = 2025.49589). Throws
/// std::invalid_argument for a month outside 1..12, a day the month does not have, or a year
/// outside 1583..9999 (the Gregorian calendar's).
TERN_API double decimal_year(int year, int month, int day);

/// Parses an ISO 8601 calendar date "YYYY-MM-DD" (exactly that: 4-digit year, 2-digit month and
/// day) and checks it is a real date. Throws std::invalid_argument, e.g.
/// "date '2025-02-30': February 2025 has 28 days".
TERN_API CalendarDate parse_iso_date(std::string_view text);

/// decimal_year() of parse_iso_date(text).
TERN_API double decimal_year(std::string_view iso_date);

}  // namespace tern
