// aero_pipeline.cpp: see aero_pipeline.hpp.
#include "aero_pipeline.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <iomanip>
#include <set>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "tern_sim_aero/model.hpp"

namespace tern::aero {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

[[noreturn]] void fail(const std::string& file, const std::string& field, const std::string& what) {
  throw std::runtime_error(file + ": " + field + ": " + what);
}

std::vector<std::string> read_lines(const std::string& path) {
  std::ifstream f(path);
  if (!f) fail(path, "file", "cannot open");
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

// Rotation of lateral quantities from stability to body axes (Beard & McLain sec. 2.2 / 4.2):
// [p_s; r_s] = T [p; r] with T = [c s; -s c]; moments [l; n]_body = T^T [l; n]_stab.
Eigen::Matrix2d stab_T(double alpha) {
  const double c = std::cos(alpha), s = std::sin(alpha);
  Eigen::Matrix2d T;
  T << c, s, -s, c;
  return T;
}

}  // namespace

// ------------------------------------------------------------------------------------ VSPAERO
//
// Layout of VSPAERO's writer (vspaero.C, CalculateStabilityDerivatives; OpenVSP, NOSA 1.3), per
// operating point:
//   ****...****                                   (VSPAERO >= 6: one line of '*' per point)
//   # Name   Value   Units                        (VSPAERO 2: "Sref_: value" without units)
//   Sref_  Cref_  Bref_  Xcg_ .. Mach_  AoA_ (deg)  Beta_ (deg)  Rho_  Vinf_  Roll__Rate ..
//   Case   Delta   Units   CFx .. CMn             (the finite-difference cases; after the seven
//   Base_Aero +0.000 n/a ...                       stability cases one row per control group,
//   <group name> +0.100 deg ...                    in ConGrp order)
//   #             Base    Derivative:
//   #             Aero    wrt ...
//   Coef   Total  Alpha  Beta  p  q  r  Mach  U  ConGrp_1 ..   (VSPAERO 2: "#  Coef  Alpha .. U",
//   #       -     per    per ...                               "Coef" being the base value)
//   #       -     rad    rad ... M  u  rad ..
//   CFx .. CS [CMl CMm CMn]  base value, then one derivative per column
//   # Result  Value  Units / SM / X_np
// CMl = -CMx, CMm = CMy, CMn = -CMz (geometry axes x aft, z up -> body x forward, z down); p, q, r
// are body rates (non-dimensional p b/2V ...); control groups per radian (Delta_Control * TORAD).
namespace {

bool all_stars(const std::string& l) {
  std::size_t n = 0;
  for (char ch : l) {
    if (ch == '*') ++n;
    else if (ch != ' ' && ch != '\t') return false;
  }
  return n >= 10;
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

struct StabPoint {
  std::size_t line = 0;                              // 1-based line of the column names
  std::map<std::string, double> header;              // Sref_, AoA_, ...
  std::vector<std::string> groups;                   // control-group names of the case list
  std::vector<std::string> cols;                     // Total Alpha Beta p q r Mach U ConGrp_1 ..
  std::vector<std::string> units;                    // per column: "per rad", "per deg", "-", ...
  std::map<std::string, std::vector<double>> rows;   // CFx .. CMn: values per column
  bool aoa_known = true;                             // false for VSPAERO 2's later tables
};

// Units of the columns from the comment rows under the column names: two rows ("per per ..",
// "rad rad .. M u ..") or one row of pairs ("per rad per deg .."); VSPAERO 2 has no unit for
// the base-value column.
std::vector<std::string> column_units(const std::string& path, std::size_t line,
                                      const std::vector<std::vector<std::string>>& unit_rows, std::size_t ncols) {
  std::vector<std::string> u;
  const std::string where = "unit rows under the column names (line " + std::to_string(line) + ")";
  if (unit_rows.empty()) fail(path, where, "missing (expected '# - per per ...' and '# - rad rad ...')");
  if (unit_rows.size() == 2 && unit_rows[0].size() == unit_rows[1].size()) {
    for (std::size_t k = 0; k < unit_rows[0].size(); ++k) {
      const std::string& a = unit_rows[0][k];
      const std::string& b = unit_rows[1][k];
      u.push_back(a == "-" && b == "-" ? "-" : a + " " + b);
    }
  } else if (unit_rows.size() == 1) {
    const auto& r = unit_rows[0];
    for (std::size_t k = 0; k < r.size(); ++k) {
      if (r[k] == "per" && k + 1 < r.size()) {
        u.push_back("per " + r[k + 1]);
        ++k;
      } else {
        u.push_back(r[k]);
      }
    }
  } else {
    fail(path, where, "the two unit rows have different lengths");
  }
  if (u.size() + 1 == ncols) u.insert(u.begin(), "-");  // VSPAERO 2: no unit for the base value
  if (u.size() != ncols)
    fail(path, where, "give " + std::to_string(u.size()) + " units for " + std::to_string(ncols) + " columns");
  return u;
}

std::vector<StabPoint> read_stab(const std::string& path) {
  static const std::set<std::string> kRows = {"CFx", "CFy", "CFz", "CMx", "CMy", "CMz",
                                              "CL",  "CD",  "CS",  "CMl", "CMm", "CMn"};
  const auto lines = read_lines(path);
  std::vector<StabPoint> pts;
  StabPoint cur;
  bool in_cases = false;
  int case_rows = 0;
  auto flush = [&] {
    if (!cur.cols.empty()) pts.push_back(cur);
    cur = StabPoint{};
  };
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string where = "line " + std::to_string(i + 1);
    if (all_stars(lines[i])) {  // a new operating point
      flush();
      in_cases = false;
      continue;
    }
    auto tk = tokens(lines[i]);
    if (tk.empty()) continue;
    if (tk[0] == "Case" && tk.size() > 2 && tk[1] == "Delta") {  // the case list (VSPAERO >= 6)
      in_cases = true;
      case_rows = 0;
      cur.groups.clear();
      continue;
    }
    if (in_cases && tk[0] == "Coef") in_cases = false;
    if (in_cases) {
      if (tk[0][0] == '#') {  // '#' lines around the rows; one after them ends the list
        if (case_rows > 0 || tk.size() > 1) in_cases = false;
        continue;
      }
      ++case_rows;
      // "<name> +0.100 deg <12 coefficients>"; names may hold spaces
      if (tk.size() < 15) fail(path, "case list " + where, "expected 'name delta units' and 12 coefficients");
      const std::size_t n = tk.size() - 14;
      double v = 0;
      for (std::size_t k = n; k < tk.size(); ++k)
        if (k != n + 1 && !to_double(tk[k], v))
          fail(path, "case list " + where, "'" + tk[k] + "' is not a number");
      const std::string name = join(std::vector<std::string>(tk.begin(), tk.begin() + static_cast<long>(n)), " ");
      static const std::set<std::string> kStab = {"Base_Aero",  "Alpha",      "Beta", "Roll__Rate",
                                                  "Pitch_Rate", "Yaw___Rate", "Mach"};
      if (!kStab.count(name)) cur.groups.push_back(name);
      continue;
    }
    const bool new_style = tk[0] == "Coef";
    const bool old_style = tk[0] == "#" && tk.size() > 2 && tk[1] == "Coef";
    if (new_style || old_style) {  // the column names, then the unit rows
      if (!cur.cols.empty()) {     // VSPAERO 2 writes one table per point without '*' lines
        StabPoint next;
        next.header = cur.header;
        next.aoa_known = false;
        flush();
        cur = next;
      }
      cur.line = i + 1;
      cur.cols.assign(tk.begin() + (new_style ? 1 : 2), tk.end());
      if (cur.cols.empty() || cur.cols[0] != "Total") cur.cols.insert(cur.cols.begin(), "Total");
      std::vector<std::vector<std::string>> unit_rows;
      std::size_t j = i + 1;
      for (; j < lines.size() && unit_rows.size() < 2; ++j) {
        auto u = tokens(lines[j]);
        if (u.empty()) continue;
        if (u[0] != "#") break;
        if (u.size() == 1) {  // a lone '#': ends the unit rows once some were read
          if (!unit_rows.empty()) break;
          continue;
        }
        unit_rows.emplace_back(u.begin() + 1, u.end());
      }
      cur.units = column_units(path, i + 1, unit_rows, cur.cols.size());
      i = j - 1;
      continue;
    }
    if (kRows.count(tk[0]) && !cur.cols.empty()) {
      if (tk.size() != cur.cols.size() + 1)
        fail(path, tk[0] + " (" + where + ")",
             "expected " + std::to_string(cur.cols.size()) + " values (" + join(cur.cols, " ") + "), found " +
                 std::to_string(tk.size() - 1));
      std::vector<double> v;
      for (std::size_t k = 1; k < tk.size(); ++k) v.push_back(number(path, tk[0] + " (" + where + ")", tk[k]));
      cur.rows[tk[0]] = v;
      continue;
    }
    // "Sref_  0.52  Lunit^2" (VSPAERO >= 6), "Sref_:  0.52" (VSPAERO 2), "SM 0.12 no_unit"
    std::string name = tk[0];
    if (!name.empty() && name.back() == ':') name.pop_back();
    if (tk.size() >= 2 && name.size() > 1 && (name.back() == '_' || name.find("__") != std::string::npos ||
                                              name == "Pitch_Rate" || name == "SM" || name == "X_np")) {
      double v = 0;
      if (!to_double(tk[1], v)) fail(path, name + " (" + where + ")", "'" + tk[1] + "' is not a number");
      cur.header[name] = v;
    }
  }
  flush();
  if (pts.empty())
    fail(path, "derivative table",
         "no 'Coef Total Alpha Beta p q r Mach U ...' column names found (not a VSPAERO .stab file?)");
  return pts;
}

}  // namespace

ToolDerivatives parse_vspaero_stab(const std::string& path, const VspaeroOptions& o) {
  if (o.controls.size() > 3) fail(path, "controls", "at most three control groups (elevator, aileron, rudder)");
  const auto pts = read_stab(path);
  ToolDerivatives t;
  t.tool = "VSPAERO";
  t.source = path;
  t.rates_in_stability_axes = false;    // VSPAERO perturbs the body rates p, q, r
  t.moments_in_stability_axes = false;  // CMl = -CMx, CMn = -CMz: body axes

  // the operating point
  auto hdr = [](const StabPoint& p, const char* k, double dflt) {
    auto it = p.header.find(k);
    return it == p.header.end() ? dflt : it->second;
  };
  std::vector<std::string> seen;
  const StabPoint* pt = nullptr;
  for (const auto& p : pts) {
    const double aoa = hdr(p, "AoA_", std::numeric_limits<double>::quiet_NaN());
    const double beta = hdr(p, "Beta_", 0.0);
    seen.push_back("AoA_ " + (p.aoa_known ? fmt(aoa) : std::string("?")) + " Beta_ " + fmt(beta));
    if (pt || std::abs(beta) > 1e-9) continue;
    if (std::isnan(o.aoa_deg) || (p.aoa_known && std::abs(aoa - o.aoa_deg) < 1e-6)) pt = &p;
  }
  if (!pt) {
    const std::string want = std::isnan(o.aoa_deg) ? std::string("Beta_ = 0")
                                                    : "AoA_ = " + fmt(o.aoa_deg) + " deg and Beta_ = 0";
    fail(path, "operating point", "none at " + want + " (the file has: " + join(seen, ", ") + ")");
  }
  if (pts.size() > 1)
    t.notes.push_back(std::to_string(pts.size()) + " operating points in the file (" + join(seen, ", ") +
                      "): read the one at line " + std::to_string(pt->line) + " (choose with --aoa)");
  const StabPoint& p = *pt;
  for (const char* k : {"Sref_", "Cref_", "Bref_", "AoA_"})
    if (!p.header.count(k)) fail(path, k, "missing in the header of the operating point");
  t.S = p.header.at("Sref_");
  t.c = p.header.at("Cref_");
  t.b = p.header.at("Bref_");
  t.alpha_ref = p.header.at("AoA_") * kDeg;
  if (p.header.count("Rho_")) {
    const double rho = p.header.at("Rho_");
    if (rho >= 0.3 && rho <= 1.6) {
      t.rho = rho;
    } else {
      t.notes.push_back("Rho_ = " + fmt(rho) +
                        " is not a plausible kg/m^3 (VSPAERO's default 0.002377 is slug/ft^3): not used");
    }
  }

  // columns: angles, rates and control groups per radian (per degree converted)
  auto col = [&](const std::string& name) -> int {
    for (std::size_t k = 0; k < p.cols.size(); ++k)
      if (p.cols[k] == name) return static_cast<int>(k);
    return -1;
  };
  std::vector<double> scale(p.cols.size(), 1.0);
  for (std::size_t k = 0; k < p.cols.size(); ++k) {
    const std::string& c = p.cols[k];
    if (!(c == "Alpha" || c == "Beta" || c == "p" || c == "q" || c == "r" || c.rfind("ConGrp_", 0) == 0)) continue;
    if (p.units[k] == "per deg") scale[k] = 1.0 / kDeg;
    else if (p.units[k] != "per rad")
      fail(path, "unit of column " + c, "'" + p.units[k] + "' (expected 'per rad' or 'per deg')");
  }
  for (const char* c : {"Total", "Alpha", "Beta", "p", "q", "r"})
    if (col(c) < 0) fail(path, "column " + std::string(c), "missing in the column names (line " + std::to_string(p.line) + ")");

  // control groups: elevator, aileron, rudder
  static const char* kRole[3] = {"elevator", "aileron", "rudder"};
  static const char* kKey[3] = {"elev", "ail", "rud"};
  std::string ctl_col[3];
  double ctl_sign[3] = {1, 1, 1};
  std::vector<std::string> groups_desc;
  for (std::size_t g = 0; g < p.groups.size(); ++g)
    groups_desc.push_back("ConGrp_" + std::to_string(g + 1) + " = " + p.groups[g]);
  const std::string groups_list = groups_desc.empty() ? std::string("no named groups") : join(groups_desc, ", ");
  std::vector<std::string> mapped;
  for (int r = 0; r < 3; ++r) {
    std::string spec = r < static_cast<int>(o.controls.size()) ? o.controls[static_cast<std::size_t>(r)] : "";
    if (spec == "none" || spec == "-") continue;
    if (!spec.empty() && spec[0] == '-') {
      ctl_sign[r] = -1;
      spec.erase(0, 1);
    }
    if (spec.empty()) {  // automatic: by the case-list name
      int found = -1, count = 0;
      for (std::size_t g = 0; g < p.groups.size(); ++g)
        if (lower(p.groups[g]).find(kKey[r]) != std::string::npos) found = static_cast<int>(g), ++count;
      if (count != 1) {
        if (count > 1)
          fail(path, std::string(kRole[r]) + " control group",
               std::string("several case-list names contain '") + kKey[r] + "' (" + groups_list + "): name it with --controls");
        continue;
      }
      ctl_col[r] = "ConGrp_" + std::to_string(found + 1);
    } else if (spec.rfind("ConGrp_", 0) == 0) {
      ctl_col[r] = spec;
    } else {
      for (std::size_t g = 0; g < p.groups.size(); ++g)
        if (lower(p.groups[g]) == lower(spec)) ctl_col[r] = "ConGrp_" + std::to_string(g + 1);
      if (ctl_col[r].empty())
        fail(path, std::string(kRole[r]) + " control group '" + spec + "'", "not in the case list (" + groups_list + ")");
    }
    if (col(ctl_col[r]) < 0)
      fail(path, std::string(kRole[r]) + " control group " + ctl_col[r],
           "no such column (columns: " + join(p.cols, " ") + ")");
    for (int q = 0; q < r; ++q)
      if (ctl_col[q] == ctl_col[r])
        fail(path, "controls", ctl_col[r] + " is both the " + kRole[q] + " and the " + kRole[r]);
    const int k = col(ctl_col[r]);
    std::string name = ctl_col[r];
    const std::size_t gi = static_cast<std::size_t>(std::stoi(ctl_col[r].substr(7)) - 1);
    if (gi < p.groups.size()) name += " (" + p.groups[gi] + ")";
    mapped.push_back(std::string(kRole[r]) + " = " + (ctl_sign[r] < 0 ? "-" : "") + name + ", " +
                     p.units[static_cast<std::size_t>(k)]);
  }
  t.notes.push_back("control groups: " + (mapped.empty() ? std::string("none read") : join(mapped, "; ")) +
                    " [file: " + groups_list + "]");

  auto get = [&](const char* row, const std::string& c, const std::string& tern, double sign = 1.0) {
    const int k = c.empty() ? -1 : col(c);
    auto it = p.rows.find(row);
    if (k < 0 || it == p.rows.end()) return;
    t.d[tern] = sign * it->second[static_cast<std::size_t>(k)] * scale[static_cast<std::size_t>(k)];
  };
  // longitudinal: wind-axis lift and drag rows; pitch CMm (VSPAERO 2: CMy, the same)
  const char* pitch = p.rows.count("CMm") ? "CMm" : "CMy";
  get("CL", "Total", "C_L");
  get("CD", "Total", "C_D");
  get(pitch, "Total", "C_m");
  const std::pair<const char*, const char*> lon[] = {{"CL", "C_L"}, {"CD", "C_D"}, {pitch, "C_m"}};
  for (const auto& [row, base] : lon) {
    const std::string b = base;
    get(row, "Alpha", b + "_alpha");
    get(row, "q", b + "_q");
    get(row, ctl_col[0], b + "_delta_e", ctl_sign[0]);
  }
  // lateral: body-axis side force CFy, rolling and yawing moments CMl, CMn (VSPAERO 2: -CMx, -CMz)
  const bool has_lmn = p.rows.count("CMl") && p.rows.count("CMn");
  const std::pair<const char*, const char*> lat[] = {
      {"CFy", "C_Y"}, {has_lmn ? "CMl" : "CMx", "C_ell"}, {has_lmn ? "CMn" : "CMz", "C_n"}};
  for (const auto& [row, base] : lat) {
    const std::string b = base;
    const double s = (!has_lmn && b != "C_Y") ? -1.0 : 1.0;
    get(row, "Beta", b + "_beta", s);
    get(row, "p", b + "_p", s);
    get(row, "r", b + "_r", s);
    get(row, ctl_col[1], b + "_delta_a", s * ctl_sign[1]);
    get(row, ctl_col[2], b + "_delta_r", s * ctl_sign[2]);
  }
  if (!has_lmn) t.notes.push_back("no CMl/CMn rows (VSPAERO 2 layout): C_ell = -CMx, C_n = -CMz, C_m = CMy");
  if (!t.d.count("C_L_alpha")) fail(path, "CL row", "missing (rows CFx .. CMn expected under the column names)");
  return t;
}

PolarFit parse_vspaero_polar(const std::string& path, double AR) {
  const auto lines = read_lines(path);
  std::vector<std::string> cols;
  std::vector<std::map<std::string, double>> rows;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    auto tk = tokens(lines[i]);
    if (tk.empty()) continue;
    if (cols.empty()) {
      if (tk[0] == "Beta" && std::find(tk.begin(), tk.end(), "AoA") != tk.end()) cols = tk;
      continue;  // VSPAERO 7 writes two title lines above the column names
    }
    const std::string where = "line " + std::to_string(i + 1);
    if (tk.size() != cols.size())
      fail(path, where, "expected " + std::to_string(cols.size()) + " columns, found " + std::to_string(tk.size()));
    std::map<std::string, double> r;
    for (std::size_t k = 0; k < tk.size(); ++k) r[cols[k]] = number(path, cols[k] + " (" + where + ")", tk[k]);
    rows.push_back(r);
  }
  if (cols.empty()) fail(path, "column names", "no 'Beta Mach AoA ...' line found (not a VSPAERO .polar?)");
  const bool has = std::find(cols.begin(), cols.end(), "CLtot") != cols.end();
  const std::string lift = has ? "CLtot" : "CL";
  for (const std::string& k : {lift, std::string("CDo"), std::string("CDi"), std::string("Mach")})
    if (std::find(cols.begin(), cols.end(), k) == cols.end())
      fail(path, k, "column missing (columns: " + join(cols, " ") + ")");
  PolarFit f;
  double sum_cdo = 0, s_xy = 0, s_xx = 0;
  const bool has_re = std::find(cols.begin(), cols.end(), "Re/1e6") != cols.end();
  double mach0 = std::numeric_limits<double>::quiet_NaN(), re0 = 0;
  int skipped = 0;
  for (auto& r : rows) {
    if (std::abs(r["Beta"]) > 1e-9) {
      ++skipped;
      continue;
    }
    if (std::isnan(mach0)) {
      mach0 = r["Mach"];
      re0 = has_re ? r["Re/1e6"] : 0.0;
    }
    if (r["Mach"] != mach0 || (has_re && r["Re/1e6"] != re0)) {
      ++skipped;
      continue;
    }
    sum_cdo += r["CDo"];
    const double x = r[lift] * r[lift] / (kPi * AR);
    s_xy += x * r["CDi"];
    s_xx += x * x;
    ++f.rows;
  }
  if (f.rows == 0) fail(path, "rows", "no data row at Beta = 0");
  if (skipped > 0)
    f.notes.push_back("used the " + std::to_string(f.rows) + " rows at Beta = 0, Mach " + fmt(mach0) +
                      (has_re ? ", Re/1e6 " + fmt(re0) : std::string()) + "; " + std::to_string(skipped) +
                      " other rows not used");
  f.C_D_p = sum_cdo / f.rows;
  if (!(s_xx > 0) || !(s_xy > 0)) fail(path, "CDi", "cannot fit an Oswald factor (" + lift + " all zero or CDi <= 0)");
  f.e = s_xx / s_xy;  // CDi = CL^2/(pi e AR): least squares of 1/e
  return f;
}

// -------------------------------------------------------------------------------------- XFLR5
//
// XFLR5 v6's panel analysis (PanelAnalysis.cpp: initializeAnalysis, setInertia,
// computeTrimmedConditions, computeNDStabDerivatives; GPL, read for the layout only) writes to
// its analysis log, for a type 7 polar:
//   Ref. area  =     0.520 m²          (XFLR5's unit setting: mm cm dm m in ft)
//   Ref. span  =     2.080 m
//   Ref. chord =     0.235 m
//   Calculation for control position  0.00      (one block per control position)
//   Mass=       4.500 kg
//   Searching for zero-moment angle... Alpha=2.00000°
//   Calculating speed to balance the weight...VInf = 15.16934 m/s
//   Longitudinal derivatives / Xu= .. Cxu= .. / Xw= .. Cxa= .. / Zu= .. Czu= .. / Zw= .. CLa= ..
//   Zq= .. CLq= .. / Mu= .. Cmu= .. / Mw= .. Cma= .. / Mq= .. Cmq= .. / Neutral Point position= .. m
//   Lateral derivatives / Yv= .. CYb= .. / Yp= .. CYp= .. / ... / Nr= .. Cnr= ..
//   Control derivatives / Xde= .. CXde= .. / Yde CYde / Zde CZde / Lde CLde / Mde CMde / Nde CNde
// Stability axes (x forward along the trim wind, z down); the rates are stability-axis rates; the
// control derivative is per radian of every surface the polar's control variable moves (with the
// sign of its gain). CLde is the ROLLING moment derivative (L), not lift.
namespace {

// "Name= value" pairs of a log line; a name is the trailing [A-Za-z0-9_] part of the token
// before '=' ("weight...VInf = 15.2" -> VInf); a value loses a trailing degree sign.
std::vector<std::pair<std::string, std::string>> pairs(const std::string& line) {
  std::string spaced;
  for (char ch : line) {
    if (ch == '=') spaced += " = ";
    else spaced += ch;
  }
  const auto tk = tokens(spaced);
  std::vector<std::pair<std::string, std::string>> out;
  for (std::size_t k = 0; k + 2 < tk.size(); ++k) {
    if (tk[k + 1] != "=" || tk[k] == "=") continue;
    std::size_t s = tk[k].size();
    while (s > 0 && (std::isalnum(static_cast<unsigned char>(tk[k][s - 1])) || tk[k][s - 1] == '_')) --s;
    std::string name = tk[k].substr(s);
    std::string v = tk[k + 2];
    static const std::string kDegSign = "\xC2\xB0";
    if (v.size() > kDegSign.size() && v.compare(v.size() - kDegSign.size(), kDegSign.size(), kDegSign) == 0)
      v.resize(v.size() - kDegSign.size());
    if (!name.empty()) out.emplace_back(name, v);
  }
  return out;
}

// XFLR5 length units (Units::getLengthUnitLabel): factor to metres; areas take the square.
double length_unit(const std::string& path, const std::string& field, std::string u, bool area) {
  static const std::string kSq = "\xC2\xB2";  // '²'
  if (area) {
    if (u.size() > kSq.size() && u.compare(u.size() - kSq.size(), kSq.size(), kSq) == 0) u.resize(u.size() - kSq.size());
    else if (u.size() > 2 && u.compare(u.size() - 2, 2, "^2") == 0) u.resize(u.size() - 2);
    else if (u.size() > 1 && u.back() == '2') u.pop_back();
    else fail(path, field, "unit '" + u + "' is not an area");
  }
  static const std::map<std::string, double> kLen = {{"mm", 1e-3}, {"cm", 1e-2}, {"dm", 0.1},
                                                     {"m", 1.0},   {"in", 0.0254}, {"ft", 0.3048}};
  auto it = kLen.find(u);
  if (it == kLen.end()) fail(path, field, "unit '" + u + "' is not one of XFLR5's (mm cm dm m in ft)");
  return area ? it->second * it->second : it->second;
}

}  // namespace

ToolDerivatives parse_xflr5(const std::string& path, const std::string& control) {
  if (!(control.empty() || control == "none" || control == "elevator" || control == "aileron" || control == "rudder"))
    fail(path, "control", "'" + control + "' (expected elevator, aileron, rudder or none)");
  const auto lines = read_lines(path);
  ToolDerivatives t;
  t.tool = "XFLR5";
  t.source = path;
  t.rates_in_stability_axes = true;
  t.moments_in_stability_axes = true;

  // reference dimensions (once, before the control positions), then one block per control position
  std::vector<std::map<std::string, std::string>> blocks(1);
  std::vector<std::string> block_title(1, "");
  for (const auto& l : lines) {
    const std::string low = lower(l);
    if (low.find("calculation for control position") != std::string::npos) {
      blocks.emplace_back();
      block_title.push_back(tokens(l).empty() ? "" : tokens(l).back());
      continue;
    }
    const auto eq = l.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = low.substr(0, eq);
    if (key.find("ref") != std::string::npos) {
      double* out = nullptr;
      bool area = false;
      std::string field;
      if (key.find("area") != std::string::npos) out = &t.S, area = true, field = "Ref. area";
      else if (key.find("span") != std::string::npos) out = &t.b, field = "Ref. span";
      else if (key.find("chord") != std::string::npos) out = &t.c, field = "Ref. chord";
      if (out) {
        const auto tk = tokens(l.substr(eq + 1));
        if (tk.empty()) fail(path, field, "no value");
        *out = number(path, field, tk[0]);
        if (tk.size() > 1) *out *= length_unit(path, field, tk[1], area);
        else t.notes.push_back(field + " has no unit: taken as metres");
        continue;
      }
    }
    for (const auto& [name, v] : pairs(l)) blocks.back().emplace(name, v);  // first one wins
  }
  std::size_t bi = 0;
  while (bi < blocks.size() && !blocks[bi].count("CLa") && !blocks[bi].count("CZa")) ++bi;
  if (bi == blocks.size())
    fail(path, "CLa", "missing (no 'Longitudinal derivatives' of a type 7 stability analysis in the file)");
  std::size_t nblocks = 0;
  for (const auto& b : blocks) nblocks += (b.count("CLa") || b.count("CZa")) ? 1 : 0;
  if (nblocks > 1)
    t.notes.push_back(std::to_string(nblocks) + " control positions in the file: read the first (" +
                      (block_title[bi].empty() ? std::string("the first block") : "position " + block_title[bi]) + ")");
  const auto& B = blocks[bi];
  auto has = [&](const char* k) { return B.count(k) > 0; };
  auto val = [&](const char* k) { return number(path, k, B.at(k)); };

  if (!has("Alpha")) fail(path, "Alpha", "missing (the trim angle of attack, 'Alpha=...°')");
  t.alpha_ref = val("Alpha") * kDeg;
  static const std::pair<const char*, const char*> kNames[] = {
      {"CLa", "C_L_alpha"}, {"CLq", "C_L_q"},   {"Cma", "C_m_alpha"}, {"Cmq", "C_m_q"},   {"Cxa", "C_X_alpha"},
      {"CYb", "C_Y_beta"},  {"CYp", "C_Y_p"},   {"CYr", "C_Y_r"},     {"Clb", "C_ell_beta"}, {"Clp", "C_ell_p"},
      {"Clr", "C_ell_r"},   {"Cnb", "C_n_beta"}, {"Cnp", "C_n_p"},    {"Cnr", "C_n_r"}};
  for (const auto& [x, tern] : kNames)
    if (has(x)) t.d[tern] = val(x);
  if (!has("CLa")) {  // newer XFLR5/flow5 logs print CZa, CZq
    t.d["C_L_alpha"] = -val("CZa");
    if (has("CZq")) t.d["C_L_q"] = -val("CZq");
  }
  if (!has("Cma")) fail(path, "Cma", "missing");

  // trim: C_m = 0 by construction; C_L and rho from q S = -VInf Zw / CLa (XFLR5 prints neither)
  t.d["C_m"] = 0.0;
  t.notes.push_back("C_m = 0 at Alpha = " + fmt(t.alpha_ref / kDeg) + " deg (XFLR5 trims to zero pitching moment)");
  if (has("Mass") && has("VInf") && has("Zw") && t.S > 0) {
    const double m = val("Mass"), u0 = val("VInf"), Zw = val("Zw");
    const double qS = -u0 * Zw / t.d["C_L_alpha"];
    const double phi = has("Phi") ? val("Phi") * kDeg : 0.0;
    if (!(qS > 0) || !(u0 > 0) || !(m > 0)) fail(path, "Zw", "q S = -VInf Zw / CLa is not positive");
    t.d["C_L"] = m * 9.81 / (qS * std::cos(phi));  // XFLR5's g
    t.rho = 2.0 * qS / (u0 * u0 * t.S);
    t.notes.push_back("C_L = m g/(q S cos phi) = " + fmt(t.d["C_L"]) + ", rho = 2 q S/(VInf^2 S) = " + fmt(t.rho) +
                      " kg/m^3, with q S = -VInf Zw/CLa (Mass " + fmt(m) + " kg, VInf " + fmt(u0) + " m/s)");
  } else {
    t.notes.push_back("no Mass/VInf/Zw lines: C_L at the trim and the density not derived");
  }
  // XFLR5's derivatives are inviscid (induced drag only). Speed changes at constant alpha scale the
  // force with u^2: Cxu = 2 C_X0 (level trim), so C_D = -Cxu/2. Stability axes held fixed:
  // C_X = -C_D + C_L dalpha, so C_D_alpha = C_L - C_X_alpha.
  if (has("Cxu")) {
    t.d["C_D"] = -0.5 * val("Cxu");
    t.notes.push_back("C_D = -Cxu/2 = " + fmt(t.d["C_D"]) + " (XFLR5's stability derivatives are inviscid: induced drag only)");
  }
  if (t.d.count("C_X_alpha") && t.d.count("C_L")) t.d["C_D_alpha"] = t.d["C_L"] - t.d["C_X_alpha"];

  // the polar's control variable
  const bool has_ctl = has("CXde") || has("CMde") || has("CLde");
  if (control == "elevator") {  // Z = -lift, X = -drag in stability axes at the trim
    if (has("CZde")) t.d["C_L_delta_e"] = -val("CZde");
    if (has("CXde")) t.d["C_D_delta_e"] = -val("CXde");
    if (has("CMde")) t.d["C_m_delta_e"] = val("CMde");
  } else if (control == "aileron" || control == "rudder") {
    const std::string s = control == "aileron" ? "_delta_a" : "_delta_r";
    if (has("CYde")) t.d["C_Y" + s] = val("CYde");
    if (has("CLde")) t.d["C_ell" + s] = val("CLde");
    if (has("CNde")) t.d["C_n" + s] = val("CNde");
  }
  if (!control.empty() && control != "none" && !has_ctl)
    fail(path, "Control derivatives", "missing (the polar has no active control; control '" + control + "' asked)");
  if (has_ctl && (control.empty() || control == "none"))
    t.notes.push_back("control derivatives (CXde .. CNde) not read: name the polar's control variable "
                      "(--xflr5-control elevator|aileron|rudder)");
  else if (has_ctl)
    t.notes.push_back("control derivatives CXde .. CNde read as the " + control + "'s (per radian)");
  return t;
}

MassProperties load_mass_file(const std::string& path) {
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    fail(path, "file", e.what());
  }
  MassProperties m;
  auto rd = [&](const YAML::Node& n, const std::string& field) {
    if (!n) fail(path, field, "missing required field");
    double v = 0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(path, field, "expected a number");
    }
    if (!std::isfinite(v)) fail(path, field, "value is not finite");
    return v;
  };
  m.mass = rd(doc["mass"], "mass");
  const YAML::Node J = doc["inertia"];
  if (!J || !J.IsMap()) fail(path, "inertia", "missing required section {Jx, Jy, Jz, Jxz}");
  m.Jx = rd(J["Jx"], "inertia.Jx");
  m.Jy = rd(J["Jy"], "inertia.Jy");
  m.Jz = rd(J["Jz"], "inertia.Jz");
  m.Jxz = rd(J["Jxz"], "inertia.Jxz");
  return m;
}

// ---------------------------------------------------------------------------------- aircraft

ImportResult build_aircraft(const ToolDerivatives& t, const MassProperties& m, const PolarFit* polar,
                            const std::string& name, const std::string& propulsion_from) {
  ImportResult r;
  sim::Aircraft& ac = r.aircraft;
  ac.name = name;
  ac.source = t.source;
  ac.mass = m.mass;
  ac.Jx = m.Jx;
  ac.Jy = m.Jy;
  ac.Jz = m.Jz;
  ac.Jxz = m.Jxz;
  if (!(t.S > 0)) fail(t.source, "reference area", "missing or not positive");
  if (!(t.b > 0)) fail(t.source, "reference span", "missing or not positive");
  if (!(t.c > 0)) fail(t.source, "reference chord", "missing or not positive");
  ac.S = t.S;
  ac.b = t.b;
  ac.c = t.c;
  auto& D = r.defaults;
  const std::string by = "not given by " + t.tool;

  // environment, stall and propulsion: not aerodynamic-analysis outputs
  ac.rho = t.rho > 0 ? t.rho : 1.225;
  if (!(t.rho > 0)) D.push_back({"environment.rho", ac.rho, by + ": ISA sea level"});
  if (!propulsion_from.empty()) {
    const sim::Aircraft p = sim::load_aircraft(propulsion_from);
    ac.prop = p.prop;
    ac.servo_tau = p.servo_tau;
    ac.max_delta_a = p.max_delta_a;
    ac.max_delta_e = p.max_delta_e;
    ac.max_delta_r = p.max_delta_r;
    ac.M = p.M;
    ac.alpha0 = p.alpha0;
    ac.stall_blend = p.stall_blend;
    ac.gear = p.gear;
    D.push_back({"propulsion.*, servos.*, gear.*, wing.M, wing.alpha0, wing.stall_blend",
                 std::numeric_limits<double>::quiet_NaN(),
                 "copied from " + propulsion_from});
  } else {
    auto& p = ac.prop;  // the Anaconda's (ROSflight anaconda_dynamics.yaml): 15 in prop, 560 KV, 6S
    p.D_prop = 0.381;
    p.C_T_0 = 0.06288743;
    p.C_T_1 = -0.02704452;
    p.C_T_2 = -0.31320732;
    p.C_Q_0 = 0.00614891;
    p.C_Q_1 = -0.0106795;
    p.C_Q_2 = -0.011779;
    p.K_V = 560.0;
    p.K_Q = 0.01705;
    p.R_motor = 0.042;
    p.i0 = 1.5;
    p.V_max = 24.0;
    ac.servo_tau = 0.01;
    ac.max_delta_a = ac.max_delta_e = ac.max_delta_r = 0.6981317;
    ac.M = 50.0;
    ac.alpha0 = 0.4712;
    ac.stall_blend = false;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    D.push_back({"propulsion.*", nan,
                 "typical: the Anaconda's motor and propeller (ROSflight; give --propulsion FILE for yours)"});
    D.push_back({"servos.*", nan, "typical: 40-degree limits, tau 0.01 s (the Anaconda's)"});
    D.push_back({"wing.M", ac.M, "typical: the book's blending rate"});
    D.push_back({"wing.alpha0", ac.alpha0, "typical: the book's stall angle (27 deg)"});
    D.push_back({"wing.stall_blend", 0.0, "false: linear lift (as ROSflight); the VLM gives no stall"});
    ac.gear.points = sim::default_gear_points(ac.b);
    D.push_back({"gear.*", std::numeric_limits<double>::quiet_NaN(), "sim_aero's default tricycle scaled by the span"});
  }

  // lateral: stability -> body axes
  auto val = [&](const std::string& k, double& out, const char* why_zero) {
    auto it = t.d.find(k);
    if (it != t.d.end()) return (out = it->second), true;
    out = 0.0;
    D.push_back({"aero." + k, 0.0, by + ": " + why_zero});
    return false;
  };
  auto& a = ac.aero;
  const Eigen::Matrix2d T = stab_T(t.alpha_ref);
  double lb = 0, nb = 0, lp = 0, lr = 0, np = 0, nr = 0, lda = 0, nda = 0, ldr = 0, ndr = 0, yp = 0, yr = 0;
  val("C_ell_beta", lb, "zero");
  val("C_n_beta", nb, "zero");
  val("C_ell_p", lp, "zero");
  val("C_ell_r", lr, "zero");
  val("C_n_p", np, "zero");
  val("C_n_r", nr, "zero");
  val("C_ell_delta_a", lda, "zero (no aileron control group)");
  val("C_n_delta_a", nda, "zero (no aileron control group)");
  val("C_ell_delta_r", ldr, "zero (no rudder control group)");
  val("C_n_delta_r", ndr, "zero (no rudder control group)");
  val("C_Y_p", yp, "zero");
  val("C_Y_r", yr, "zero");
  val("C_Y_beta", a.C_Y_beta, "zero");
  val("C_Y_delta_a", a.C_Y_delta_a, "zero");
  val("C_Y_delta_r", a.C_Y_delta_r, "zero");
  // moment rows: [l; n]_body = T^T [l; n]_stab (XFLR5); VSPAERO's are body-axis moments already
  const Eigen::Matrix2d Rm = t.moments_in_stability_axes ? Eigen::Matrix2d(T.transpose()) : Eigen::Matrix2d::Identity();
  const Eigen::Vector2d beta_b = Rm * Eigen::Vector2d(lb, nb);
  const Eigen::Vector2d da_b = Rm * Eigen::Vector2d(lda, nda);
  const Eigen::Vector2d dr_b = Rm * Eigen::Vector2d(ldr, ndr);
  Eigen::Matrix2d Dr;
  Dr << lp, lr, np, nr;
  Eigen::RowVector2d Yr(yp, yr);
  if (t.rates_in_stability_axes) {  // rate columns: [p; r]_stab = T [p; r]_body
    Dr = (Rm * Dr * T).eval();
    Yr = (Yr * T).eval();
  } else {
    Dr = (Rm * Dr).eval();
  }
  a.C_ell_beta = beta_b(0);
  a.C_n_beta = beta_b(1);
  a.C_ell_delta_a = da_b(0);
  a.C_n_delta_a = da_b(1);
  a.C_ell_delta_r = dr_b(0);
  a.C_n_delta_r = dr_b(1);
  a.C_ell_p = Dr(0, 0);
  a.C_ell_r = Dr(0, 1);
  a.C_n_p = Dr(1, 0);
  a.C_n_r = Dr(1, 1);
  a.C_Y_p = Yr(0);
  a.C_Y_r = Yr(1);
  a.C_Y_0 = a.C_ell_0 = a.C_n_0 = 0.0;
  D.push_back({"aero.C_Y_0, C_ell_0, C_n_0", 0.0, "zero: symmetric aircraft"});

  // longitudinal (lift, drag and pitch are the same in stability and body-pitch terms)
  val("C_L_alpha", a.C_L_alpha, "zero");
  val("C_L_q", a.C_L_q, "zero");
  val("C_L_delta_e", a.C_L_delta_e, "zero (no elevator control group)");
  val("C_m_alpha", a.C_m_alpha, "zero");
  val("C_m_q", a.C_m_q, "zero");
  val("C_m_delta_e", a.C_m_delta_e, "zero (no elevator control group)");
  val("C_D_q", a.C_D_q, "zero (negligible; the book's value)");
  val("C_D_delta_e", a.C_D_delta_e, "zero");
  double CL = 0, Cm = 0, CD = 0;
  if (val("C_L", CL, "zero lift at alpha_ref")) a.C_L_0 = CL - a.C_L_alpha * t.alpha_ref;
  else a.C_L_0 = -a.C_L_alpha * t.alpha_ref;
  if (val("C_m", Cm, "zero pitching moment at alpha_ref")) a.C_m_0 = Cm - a.C_m_alpha * t.alpha_ref;
  else a.C_m_0 = -a.C_m_alpha * t.alpha_ref;
  const bool have_CD = val("C_D", CD, "zero drag at alpha_ref");
  val("C_D_alpha", a.C_D_alpha, "zero");
  a.C_D_0 = CD - a.C_D_alpha * t.alpha_ref;
  if (polar != nullptr) {
    a.C_D_p = polar->C_D_p;
    ac.e = polar->e;
  } else {
    ac.e = 0.9;
    D.push_back({"wing.e", ac.e, "no .polar: typical Oswald efficiency"});
    const double cdp = have_CD ? CD - CL * CL / (kPi * ac.e * ac.AR()) : 0.0;
    if (cdp > 0.005) {
      a.C_D_p = cdp;
      D.push_back({"aero.C_D_p", cdp, "no .polar: C_D - C_L^2/(pi e AR) at alpha_ref"});
    } else {
      a.C_D_p = 0.03;
      D.push_back({"aero.C_D_p", 0.03, "no .polar and no viscous drag in the analysis: typical small UAV"});
    }
  }
  sim::validate(ac);
  return r;
}

std::string aircraft_yaml(const sim::Aircraft& ac, const std::vector<std::string>& header) {
  std::ostringstream o;
  o << std::setprecision(10);
  for (const auto& h : header) o << "# " << h << "\n";
  const auto& a = ac.aero;
  const auto& p = ac.prop;
  o << "name: " << ac.name << "\nmass: " << ac.mass << "\ninertia:\n  Jx: " << ac.Jx << "\n  Jy: " << ac.Jy
    << "\n  Jz: " << ac.Jz << "\n  Jxz: " << ac.Jxz << "\nenvironment:\n  rho: " << ac.rho << "\nwing:\n  S: " << ac.S
    << "\n  b: " << ac.b << "\n  c: " << ac.c << "\n  e: " << ac.e << "\n  M: " << ac.M << "\n  alpha0: " << ac.alpha0
    << "\n  stall_blend: " << (ac.stall_blend ? "true" : "false") << "\naero:\n";
  const std::pair<const char*, double> co[] = {
      {"C_L_0", a.C_L_0}, {"C_L_alpha", a.C_L_alpha}, {"C_L_q", a.C_L_q}, {"C_L_delta_e", a.C_L_delta_e},
      {"C_D_p", a.C_D_p}, {"C_D_q", a.C_D_q}, {"C_D_delta_e", a.C_D_delta_e}, {"C_D_0", a.C_D_0},
      {"C_D_alpha", a.C_D_alpha}, {"C_m_0", a.C_m_0}, {"C_m_alpha", a.C_m_alpha}, {"C_m_q", a.C_m_q},
      {"C_m_delta_e", a.C_m_delta_e}, {"C_Y_0", a.C_Y_0}, {"C_Y_beta", a.C_Y_beta}, {"C_Y_p", a.C_Y_p},
      {"C_Y_r", a.C_Y_r}, {"C_Y_delta_a", a.C_Y_delta_a}, {"C_Y_delta_r", a.C_Y_delta_r},
      {"C_ell_0", a.C_ell_0}, {"C_ell_beta", a.C_ell_beta}, {"C_ell_p", a.C_ell_p}, {"C_ell_r", a.C_ell_r},
      {"C_ell_delta_a", a.C_ell_delta_a}, {"C_ell_delta_r", a.C_ell_delta_r}, {"C_n_0", a.C_n_0},
      {"C_n_beta", a.C_n_beta}, {"C_n_p", a.C_n_p}, {"C_n_r", a.C_n_r}, {"C_n_delta_a", a.C_n_delta_a},
      {"C_n_delta_r", a.C_n_delta_r}};
  for (const auto& [k, v] : co) o << "  " << k << ": " << v << "\n";
  o << "propulsion:\n  D_prop: " << p.D_prop << "\n  C_T_0: " << p.C_T_0 << "\n  C_T_1: " << p.C_T_1
    << "\n  C_T_2: " << p.C_T_2 << "\n  C_Q_0: " << p.C_Q_0 << "\n  C_Q_1: " << p.C_Q_1 << "\n  C_Q_2: " << p.C_Q_2
    << "\n  K_Q: " << p.K_Q << "\n  R_motor: " << p.R_motor << "\n  i0: " << p.i0 << "\n  V_max: " << p.V_max
    << "\nservos:\n  tau: " << ac.servo_tau << "\n  max_delta_a: " << ac.max_delta_a
    << "\n  max_delta_e: " << ac.max_delta_e << "\n  max_delta_r: " << ac.max_delta_r << "\n";
  return o.str();
}

// --------------------------------------------------------------------------------- linearize

LinearModel linearize(const sim::Aircraft& ac, const sim::TrimRequest& req) {
  LinearModel lm;
  lm.Va = req.Va;
  lm.trim = sim::compute_trim(ac, req);
  const sim::TrimResult& tr = lm.trim;
  const sim::StateVector& xs = tr.x;
  const double phi0 = tr.phi, theta0 = tr.theta, psi0 = req.psi, h0 = -xs[sim::PD];
  const sim::Wind calm;
  // full reduced state z = [u v w p q r phi theta psi h], inputs [de da dr dt]
  using Z = Eigen::Matrix<double, 10, 1>;
  using In = Eigen::Vector4d;
  Z z0;
  z0 << xs[sim::U], xs[sim::V], xs[sim::W], xs[sim::P], xs[sim::Q], xs[sim::R], phi0, theta0, psi0, h0;
  const In in0(tr.delta.delta_e, tr.delta.delta_a, tr.delta.delta_r, tr.delta.delta_t);
  auto f = [&](const Z& z, const In& in) {
    const sim::StateVector x = sim::make_state({0, 0, -z[9]}, {z[0], z[1], z[2]}, z[6], z[7], z[8], {z[3], z[4], z[5]});
    sim::Deltas d;
    d.delta_e = in[0];
    d.delta_a = in[1];
    d.delta_r = in[2];
    d.delta_t = in[3];
    const sim::StateVector dx = sim::derivative(ac, x, d, calm);
    const double sp = std::sin(z[6]), cp = std::cos(z[6]), tt = std::tan(z[7]), ct = std::cos(z[7]);
    Z dz;
    dz << dx[sim::U], dx[sim::V], dx[sim::W], dx[sim::P], dx[sim::Q], dx[sim::R],
        z[3] + z[4] * sp * tt + z[5] * cp * tt,  // book eq. 3.3
        z[4] * cp - z[5] * sp, (z[4] * sp + z[5] * cp) / ct, -dx[sim::PD];
    return dz;
  };
  Eigen::Matrix<double, 10, 10> A;
  Eigen::Matrix<double, 10, 4> B;
  for (int j = 0; j < 10; ++j) {
    const double h = 1e-5 * std::max(1.0, std::abs(z0[j]));
    Z zp = z0, zm = z0;
    zp[j] += h;
    zm[j] -= h;
    A.col(j) = (f(zp, in0) - f(zm, in0)) / (2 * h);
  }
  for (int j = 0; j < 4; ++j) {
    const double h = 1e-6;
    In ip = in0, im = in0;
    ip[j] += h;
    im[j] -= h;
    B.col(j) = (f(z0, ip) - f(z0, im)) / (2 * h);
  }
  const int lon[5] = {0, 2, 4, 7, 9}, lat[5] = {1, 3, 5, 6, 8};
  const int ulon[2] = {0, 3}, ulat[2] = {1, 2};
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      lm.A_lon(i, j) = A(lon[i], lon[j]);
      lm.A_lat(i, j) = A(lat[i], lat[j]);
    }
    for (int j = 0; j < 2; ++j) {
      lm.B_lon(i, j) = B(lon[i], ulon[j]);
      lm.B_lat(i, j) = B(lat[i], ulat[j]);
    }
  }
  // transfer-function coefficients (book sec. 5.4, a_V1/a_V2 with the propeller model)
  const auto& a = ac.aero;
  const double Va = req.Va, rho = ac.rho, S = ac.S, b = ac.b, c = ac.c, m = ac.mass;
  const double Gam = ac.Jx * ac.Jz - ac.Jxz * ac.Jxz;
  const double G3 = ac.Jz / Gam, G4 = ac.Jxz / Gam;
  const double Cpp = G3 * a.C_ell_p + G4 * a.C_n_p;
  const double Cpda = G3 * a.C_ell_delta_a + G4 * a.C_n_delta_a;
  auto& k = lm.tf;
  k["a_phi1"] = -0.5 * rho * Va * Va * S * b * Cpp * b / (2 * Va);
  k["a_phi2"] = 0.5 * rho * Va * Va * S * b * Cpda;
  const double qc = rho * Va * Va * c * S / (2 * ac.Jy);
  k["a_theta1"] = -qc * a.C_m_q * c / (2 * Va);
  k["a_theta2"] = -qc * a.C_m_alpha;
  k["a_theta3"] = qc * a.C_m_delta_e;
  const double dt = tr.delta.delta_t, hv = 1e-4;
  const double dT_dVa = (sim::propulsion(ac, Va + hv, dt).T_p - sim::propulsion(ac, Va - hv, dt).T_p) / (2 * hv);
  const double dT_ddt = (sim::propulsion(ac, Va, dt + hv).T_p - sim::propulsion(ac, Va, dt - hv).T_p) / (2 * hv);
  k["a_V1"] = rho * Va * S / m * (sim::drag_coefficient(ac, tr.alpha) + a.C_D_delta_e * tr.delta.delta_e) - dT_dVa / m;
  k["a_V2"] = dT_ddt / m;
  k["a_V3"] = sim::kG * std::cos(tr.theta - tr.alpha);
  k["a_beta1"] = -rho * Va * S / (2 * m) * a.C_Y_beta;
  k["a_beta2"] = rho * Va * S / (2 * m) * a.C_Y_delta_r;
  return lm;
}

// ------------------------------------------------------------------------------------- gains

std::vector<std::pair<std::string, double>> design_gains(const LinearModel& lm, const DesignOptions& o) {
  const auto& k = lm.tf;
  const double Va = lm.Va, g = sim::kG;
  std::vector<std::pair<std::string, double>> out;
  // roll (sec. 6.1.1): closed loop s^2 + (a_phi1 + a_phi2 kd) s + a_phi2 kp
  const double wn_phi = std::isnan(o.wn_phi) ? k.at("a_phi1") / (2 * o.zeta_phi) : o.wn_phi;
  const double roll_kp = wn_phi * wn_phi / k.at("a_phi2");
  const double roll_kd = std::max(0.0, (2 * o.zeta_phi * wn_phi - k.at("a_phi1")) / k.at("a_phi2"));
  out.push_back({"roll_kp", roll_kp});
  out.push_back({"roll_kd", roll_kd});
  out.push_back({"roll_ki", 0.0});
  // course (sec. 6.1.2): P bandwidth wn_phi / W_chi, slow integrator T_chi
  const double wc = std::sqrt(k.at("a_phi2") * roll_kp) / o.W_chi;
  const double course_kp = wc * Va / g;
  out.push_back({"course_kp", course_kp});
  out.push_back({"course_ki", course_kp / o.T_chi});
  out.push_back({"course_kd", 0.0});
  // pitch (sec. 6.2.1); tern's pitch gains are magnitudes (the book's are negative)
  const double a1 = k.at("a_theta1"), a2 = k.at("a_theta2"), a3 = k.at("a_theta3");
  const double kp_th = o.K_theta_DC * a2 / ((1 - o.K_theta_DC) * a3);
  const double wn_th = std::sqrt(a2 + kp_th * a3);
  const double kd_th = (2 * o.zeta_theta * wn_th - a1) / a3;
  const double K_dc = kp_th * a3 / (a2 + kp_th * a3);
  out.push_back({"pitch_kp", -kp_th});
  out.push_back({"pitch_kd", std::max(0.0, -kd_th)});
  out.push_back({"pitch_ki", o.pitch_ki_ratio * (-kp_th) * wn_th});
  // altitude from pitch (sec. 6.2.2, eq. 6.24)
  const double wn_h = wn_th / o.W_h;
  out.push_back({"altitude_ki", wn_h * wn_h / (K_dc * Va)});
  out.push_back({"altitude_kp", 2 * o.zeta_h * wn_h / (K_dc * Va)});
  out.push_back({"altitude_kd", 0.0});
  // airspeed with throttle (sec. 6.2.4, eq. 6.29)
  out.push_back({"airspeed_ki", o.wn_V * o.wn_V / k.at("a_V2")});
  out.push_back({"airspeed_kp", std::max(0.0, (2 * o.zeta_V * o.wn_V - k.at("a_V1")) / k.at("a_V2"))});
  out.push_back({"airspeed_kd", 0.0});
  // yaw damper (sec. 6.1.3)
  out.push_back({"yaw_damper_kr", o.kr});
  out.push_back({"yaw_damper_p_wo", o.p_wo});
  out.push_back({"trim_e", lm.trim.delta.delta_e});
  out.push_back({"trim_t", lm.trim.delta.delta_t});
  return out;
}

}  // namespace tern::aero
