// Calendar dates for the World Magnetic Model (see tern/magnetic_model.hpp): ISO "YYYY-MM-DD"
// text and NOAA's decimal year. Day counts are GeographicLib's (Utility::day, Gregorian).
#include <stdexcept>
#include <string>

#include <GeographicLib/Utility.hpp>
#include <fmt/format.h>

#include "tern/magnetic_model.hpp"

namespace tern {
namespace {

constexpr const char* kMonthNames[] = {"January", "February", "March",     "April",   "May",      "June",
                                       "July",    "August",   "September", "October", "November", "December"};

bool is_leap(int y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

int days_in_month(int y, int m) {
  constexpr int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return m == 2 && is_leap(y) ? 29 : kDays[m - 1];
}

/// "" for a valid Gregorian date, else why not.
std::string date_problem(int year, int month, int day) {
  if (year < 1583 || year > 9999) return fmt::format("year {} is outside 1583..9999 (the Gregorian calendar)", year);
  if (month < 1 || month > 12) return fmt::format("month {} is outside 1..12", month);
  if (day < 1 || day > days_in_month(year, month))
    return fmt::format("{} {} has {} days, not day {}", kMonthNames[month - 1], year, days_in_month(year, month), day);
  return "";
}

bool is_digits(std::string_view s) {
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}

}  // namespace

double decimal_year(int year, int month, int day) {
  const std::string why = date_problem(year, month, day);
  if (!why.empty()) throw std::invalid_argument(fmt::format("date {:04d}-{:02d}-{:02d}: {}", year, month, day, why));
  using GeographicLib::Utility;
  const int first = Utility::day(year, 1, 1), next = Utility::day(year + 1, 1, 1);
  return year + static_cast<double>(Utility::day(year, month, day) - first) / (next - first);
}

CalendarDate parse_iso_date(std::string_view text) {
  const bool shape = text.size() == 10 && text[4] == '-' && text[7] == '-' && is_digits(text.substr(0, 4)) &&
                     is_digits(text.substr(5, 2)) && is_digits(text.substr(8, 2));
  if (!shape) throw std::invalid_argument(fmt::format("date '{}': expected an ISO date YYYY-MM-DD, e.g. 2025-07-01", text));
  const auto num = [&](std::size_t pos, std::size_t len) { return std::stoi(std::string(text.substr(pos, len))); };
  const CalendarDate d{num(0, 4), num(5, 2), num(8, 2)};
  const std::string why = date_problem(d.year, d.month, d.day);
  if (!why.empty()) throw std::invalid_argument(fmt::format("date '{}': {}", text, why));
  return d;
}

double decimal_year(std::string_view iso_date) {
  const CalendarDate d = parse_iso_date(iso_date);
  return decimal_year(d.year, d.month, d.day);
}

}  // namespace tern
