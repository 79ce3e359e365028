// aero_text.cpp: see aero_text.hpp.
#include "aero_text.hpp"

#include <cctype>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "tern/input_file.hpp"

namespace tern::aero::text {

void fail(const std::string& file, const std::string& field, const std::string& what) {
  throw std::runtime_error(file + ": " + field + ": " + what);
}

std::vector<std::string> read_lines(const std::string& path) {
  std::istringstream f(read_text_file(path, "file"));  // a regular file of at most kMaxTextFileBytes
  std::vector<std::string> lines;
  std::string l;
  while (std::getline(f, l)) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    lines.push_back(l);
  }
  return lines;
}

std::vector<std::string> tokens(const std::string& s) {
  std::istringstream is(s);
  std::vector<std::string> t;
  std::string w;
  while (is >> w) t.push_back(w);
  return t;
}

bool to_double(const std::string& s, double& v) {
  try {
    std::size_t n = 0;
    v = std::stod(s, &n);
    return n == s.size() && std::isfinite(v);
  } catch (const std::exception&) {
    return false;
  }
}

double number(const std::string& file, const std::string& field, const std::string& s) {
  double v = 0;
  if (!to_double(s, v)) fail(file, field, "'" + s + "' is not a finite number");
  return v;
}

std::string lower(std::string s) {
  for (auto& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
  return s;
}

std::string fmt(double v) {
  std::ostringstream o;
  o << std::setprecision(6) << v;
  return o.str();
}

}  // namespace tern::aero::text
