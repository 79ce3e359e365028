// import_vspaero.cpp: VSPAERO .stab and .polar readers of `tern aero import` (see tern/aero/import.hpp).
#include "tern/aero/import.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "aero_text.hpp"

namespace tern::aero {
using namespace text;

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
    if (ch == '*')
      ++n;
    else if (ch != ' ' && ch != '\t')
      return false;
  }
  return n >= 10;
}

struct StabPoint {
  std::size_t line = 0;                             // 1-based line of the column names
  std::map<std::string, double> header;             // Sref_, AoA_, ...
  std::vector<std::string> groups;                  // control-group names of the case list
  std::vector<std::string> cols;                    // Total Alpha Beta p q r Mach U ConGrp_1 ..
  std::vector<std::string> units;                   // per column: "per rad", "per deg", "-", ...
  std::map<std::string, std::vector<double>> rows;  // CFx .. CMn: values per column
  bool aoa_known = true;                            // false for VSPAERO 2's later tables
};

// Units of the columns from the comment rows under the column names: two rows ("per per ..",
// "rad rad .. M u ..") or one row of pairs ("per rad per deg .."); VSPAERO 2 has no unit for
// the base-value column.
std::vector<std::string> column_units(const std::string& path, std::size_t line, const std::vector<std::vector<std::string>>& unit_rows,
                                      std::size_t ncols) {
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
  if (u.size() != ncols) fail(path, where, "give " + std::to_string(u.size()) + " units for " + std::to_string(ncols) + " columns");
  return u;
}

std::vector<StabPoint> read_stab(const std::string& path) {
  static const std::set<std::string> kRows = {"CFx", "CFy", "CFz", "CMx", "CMy", "CMz", "CL", "CD", "CS", "CMl", "CMm", "CMn"};
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
        if (k != n + 1 && !to_double(tk[k], v)) fail(path, "case list " + where, "'" + tk[k] + "' is not a number");
      const std::string name = join(std::vector<std::string>(tk.begin(), tk.begin() + static_cast<long>(n)), " ");
      static const std::set<std::string> kStab = {"Base_Aero", "Alpha", "Beta", "Roll__Rate", "Pitch_Rate", "Yaw___Rate", "Mach"};
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
    if (tk.size() >= 2 && name.size() > 1 &&
        (name.back() == '_' || name.find("__") != std::string::npos || name == "Pitch_Rate" || name == "SM" || name == "X_np")) {
      double v = 0;
      if (!to_double(tk[1], v)) fail(path, name + " (" + where + ")", "'" + tk[1] + "' is not a number");
      cur.header[name] = v;
    }
  }
  flush();
  if (pts.empty())
    fail(path, "derivative table", "no 'Coef Total Alpha Beta p q r Mach U ...' column names found (not a VSPAERO .stab file?)");
  return pts;
}

// The operating point to read (Beta_ = 0): the one at AoA_ = aoa_deg, or with aoa_deg NaN the one
// nearest zero angle of attack (the first of equals; VSPAERO 2's later tables, whose AoA_ is not
// written, only if no table has one). Says which in `notes`.
const StabPoint& choose_point(const std::string& path, const std::vector<StabPoint>& pts, double aoa_deg, std::vector<std::string>& notes) {
  auto aoa_of = [](const StabPoint& p) {
    auto it = p.header.find("AoA_");
    return p.aoa_known && it != p.header.end() ? it->second : std::numeric_limits<double>::quiet_NaN();
  };
  auto beta_of = [](const StabPoint& p) {
    auto it = p.header.find("Beta_");
    return it == p.header.end() ? 0.0 : it->second;
  };
  std::vector<std::string> seen;
  const StabPoint* pt = nullptr;
  for (const auto& p : pts) {
    const double aoa = aoa_of(p), beta = beta_of(p);
    seen.push_back("AoA_ " + (std::isnan(aoa) ? std::string("?") : fmt(aoa)) + " Beta_ " + fmt(beta));
    if (std::abs(beta) > 1e-9) continue;
    if (!std::isnan(aoa_deg)) {
      if (!pt && !std::isnan(aoa) && std::abs(aoa - aoa_deg) < 1e-6) pt = &p;
    } else if (!pt || (std::isnan(aoa_of(*pt)) && !std::isnan(aoa)) || (!std::isnan(aoa) && std::abs(aoa) < std::abs(aoa_of(*pt)))) {
      pt = &p;
    }
  }
  if (!pt) {
    const std::string want = std::isnan(aoa_deg) ? std::string("Beta_ = 0") : "AoA_ = " + fmt(aoa_deg) + " deg and Beta_ = 0";
    fail(path, "operating point", "none at " + want + " (the file has: " + join(seen, ", ") + ")");
  }
  const double aoa = aoa_of(*pt);
  const std::string which =
      "AoA_ " + (std::isnan(aoa) ? std::string("?") : fmt(aoa)) + " deg, Beta_ 0 (line " + std::to_string(pt->line) + ")";
  if (!std::isnan(aoa_deg))
    notes.push_back("operating point: " + which + ", as --aoa asked");
  else if (pts.size() > 1)
    notes.push_back("operating point: " + which + ", the one nearest zero angle of attack of the " + std::to_string(pts.size()) +
                    " in the file (" + join(seen, ", ") + "; choose another with --aoa DEG)");
  else
    notes.push_back("operating point: " + which);
  return *pt;
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

  const StabPoint& p = choose_point(path, pts, o.aoa_deg, t.notes);
  for (const char* k : {"Sref_", "Cref_", "Bref_", "AoA_"})
    if (!p.header.count(k)) fail(path, k, "missing in the header of the operating point");
  t.S = p.header.at("Sref_");
  t.c = p.header.at("Cref_");
  t.b = p.header.at("Bref_");
  t.alpha_ref = p.header.at("AoA_") * kRadPerDeg;
  if (p.header.count("Rho_")) {
    const double rho = p.header.at("Rho_");
    if (rho >= 0.3 && rho <= 1.6) {
      t.rho = rho;
    } else {
      t.notes.push_back("Rho_ = " + fmt(rho) + " is not a plausible kg/m^3 (VSPAERO's default 0.002377 is slug/ft^3): not used");
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
    if (p.units[k] == "per deg")
      scale[k] = 1.0 / kRadPerDeg;
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
  for (std::size_t g = 0; g < p.groups.size(); ++g) groups_desc.push_back("ConGrp_" + std::to_string(g + 1) + " = " + p.groups[g]);
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
      fail(path, std::string(kRole[r]) + " control group " + ctl_col[r], "no such column (columns: " + join(p.cols, " ") + ")");
    for (int q = 0; q < r; ++q)
      if (ctl_col[q] == ctl_col[r]) fail(path, "controls", ctl_col[r] + " is both the " + kRole[q] + " and the " + kRole[r]);
    const int k = col(ctl_col[r]);
    std::string name = ctl_col[r];
    // the group's name when the column is ConGrp_<n> of the case list (a column named otherwise, e.g.
    // ConGrp_x or a number past any int, has none: never std::stoi's exception)
    const std::string n_text = ctl_col[r].substr(7);
    std::size_t n = 0;
    const auto [end, ec] = std::from_chars(n_text.data(), n_text.data() + n_text.size(), n);
    if (ec == std::errc() && end == n_text.data() + n_text.size() && n >= 1 && n <= p.groups.size()) name += " (" + p.groups[n - 1] + ")";
    mapped.push_back(std::string(kRole[r]) + " = " + (ctl_sign[r] < 0 ? "-" : "") + name + ", " + p.units[static_cast<std::size_t>(k)]);
  }
  t.notes.push_back("control groups: " + (mapped.empty() ? std::string("none read") : join(mapped, "; ")) + " [file: " + groups_list + "]");

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
  const std::pair<const char*, const char*> lat[] = {{"CFy", "C_Y"}, {has_lmn ? "CMl" : "CMx", "C_ell"}, {has_lmn ? "CMn" : "CMz", "C_n"}};
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
    if (std::find(cols.begin(), cols.end(), k) == cols.end()) fail(path, k, "column missing (columns: " + join(cols, " ") + ")");
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
                      (has_re ? ", Re/1e6 " + fmt(re0) : std::string()) + "; " + std::to_string(skipped) + " other rows not used");
  f.C_D_p = sum_cdo / f.rows;
  if (!(s_xx > 0) || !(s_xy > 0)) fail(path, "CDi", "cannot fit an Oswald factor (" + lift + " all zero or CDi <= 0)");
  f.e = s_xx / s_xy;  // CDi = CL^2/(pi e AR): least squares of 1/e
  return f;
}

}  // namespace tern::aero
