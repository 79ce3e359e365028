// import_xflr5.cpp: XFLR5 v6 analysis-log reader of `tern aero import` (see tern/aero/import.hpp).
#include "tern/aero/import.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "aero_text.hpp"

namespace tern::aero {
using namespace text;

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
    if (ch == '=')
      spaced += " = ";
    else
      spaced += ch;
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
    if (u.size() > kSq.size() && u.compare(u.size() - kSq.size(), kSq.size(), kSq) == 0)
      u.resize(u.size() - kSq.size());
    else if (u.size() > 2 && u.compare(u.size() - 2, 2, "^2") == 0)
      u.resize(u.size() - 2);
    else if (u.size() > 1 && u.back() == '2')
      u.pop_back();
    else
      fail(path, field, "unit '" + u + "' is not an area");
  }
  static const std::map<std::string, double> kLen = {{"mm", 1e-3}, {"cm", 1e-2}, {"dm", 0.1}, {"m", 1.0}, {"in", 0.0254}, {"ft", 0.3048}};
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
      if (key.find("area") != std::string::npos)
        out = &t.S, area = true, field = "Ref. area";
      else if (key.find("span") != std::string::npos)
        out = &t.b, field = "Ref. span";
      else if (key.find("chord") != std::string::npos)
        out = &t.c, field = "Ref. chord";
      if (out) {
        const auto tk = tokens(l.substr(eq + 1));
        if (tk.empty()) fail(path, field, "no value");
        *out = number(path, field, tk[0]);
        if (tk.size() > 1)
          *out *= length_unit(path, field, tk[1], area);
        else
          t.notes.push_back(field + " has no unit: taken as metres");
        continue;
      }
    }
    for (const auto& [name, v] : pairs(l)) blocks.back().emplace(name, v);  // first one wins
  }
  std::size_t bi = 0;
  while (bi < blocks.size() && !blocks[bi].count("CLa") && !blocks[bi].count("CZa")) ++bi;
  if (bi == blocks.size()) fail(path, "CLa", "missing (no 'Longitudinal derivatives' of a type 7 stability analysis in the file)");
  std::size_t nblocks = 0;
  for (const auto& b : blocks) nblocks += (b.count("CLa") || b.count("CZa")) ? 1 : 0;
  if (nblocks > 1)
    t.notes.push_back(std::to_string(nblocks) + " control positions in the file: read the first (" +
                      (block_title[bi].empty() ? std::string("the first block") : "position " + block_title[bi]) + ")");
  const auto& B = blocks[bi];
  auto has = [&](const char* k) { return B.count(k) > 0; };
  auto val = [&](const char* k) { return number(path, k, B.at(k)); };

  if (!has("Alpha")) fail(path, "Alpha", "missing (the trim angle of attack, 'Alpha=...°')");
  t.alpha_ref = val("Alpha") * kRadPerDeg;
  static const std::pair<const char*, const char*> kNames[] = {
      {"CLa", "C_L_alpha"}, {"CLq", "C_L_q"},    {"Cma", "C_m_alpha"}, {"Cmq", "C_m_q"},      {"Cxa", "C_X_alpha"},
      {"CYb", "C_Y_beta"},  {"CYp", "C_Y_p"},    {"CYr", "C_Y_r"},     {"Clb", "C_ell_beta"}, {"Clp", "C_ell_p"},
      {"Clr", "C_ell_r"},   {"Cnb", "C_n_beta"}, {"Cnp", "C_n_p"},     {"Cnr", "C_n_r"}};
  for (const auto& [x, tern] : kNames)
    if (has(x)) t.d[tern] = val(x);
  if (!has("CLa")) {  // newer XFLR5/flow5 logs print CZa, CZq
    t.d["C_L_alpha"] = -val("CZa");
    if (has("CZq")) t.d["C_L_q"] = -val("CZq");
  }
  if (!has("Cma")) fail(path, "Cma", "missing");

  // trim: C_m = 0 by construction; C_L and rho from q S = -VInf Zw / CLa (XFLR5 prints neither)
  t.d["C_m"] = 0.0;
  t.notes.push_back("C_m = 0 at Alpha = " + fmt(t.alpha_ref / kRadPerDeg) + " deg (XFLR5 trims to zero pitching moment)");
  if (has("Mass") && has("VInf") && has("Zw") && t.S > 0) {
    const double m = val("Mass"), u0 = val("VInf"), Zw = val("Zw");
    const double qS = -u0 * Zw / t.d["C_L_alpha"];
    const double phi = has("Phi") ? val("Phi") * kRadPerDeg : 0.0;
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
    t.notes.push_back(
        "control derivatives (CXde .. CNde) not read: name the polar's control variable "
        "(--xflr5-control elevator|aileron|rudder)");
  else if (has_ctl)
    t.notes.push_back("control derivatives CXde .. CNde read as the " + control + "'s (per radian)");
  return t;
}

}  // namespace tern::aero
