// core/apps/sysid/tests/test_prior_update.cpp: held terms moved with an identified derivative of the
// same surface (sysid/prior_update.hpp): which move, by how much, and what the result then says.
#include <doctest/doctest.h>

#include <string>

#include "sysid/prior_update.hpp"
#include "sysid/sysid_output.hpp"
#include "tern/aircraft.hpp"

using namespace tern;
using namespace tern::core::sysid;

namespace {

const std::string kAerosonde = std::string(TERN_AIRCRAFT_DIR) + "/aerosonde.yaml";

CoefficientEstimate estimate(const std::string& name, double prior, double value, bool identified) {
  CoefficientEstimate e;
  e.name = name, e.prior = prior, e.estimate = value, e.identified = identified, e.std_error = identified ? 0.01 : 0.0;
  e.note = identified ? "" : "poorly determined: 1 +- 9";
  return e;
}

}  // namespace

TEST_CASE("scaled_prior: a paired term takes its surface's identified-over-prior ratio, held or identified; nothing else moves") {
  const Aircraft prior = load_aircraft(kAerosonde);
  const AeroCoefficients& p = prior.aero;
  SysidResult pass;
  pass.coefficients = {estimate("C_m_delta_e", p.C_m_delta_e, 1.5 * p.C_m_delta_e, true),  // the elevator 1.5x the prior
                       estimate("C_L_delta_e", p.C_L_delta_e, p.C_L_delta_e, false),
                       estimate("C_m_q", p.C_m_q, 0.7 * p.C_m_q, true),
                       estimate("C_L_q", p.C_L_q, 3.0, true),  // identified: its prior moves all the same (the next pass may hold it)
                       estimate("C_ell_delta_a", p.C_ell_delta_a, 5.0 * p.C_ell_delta_a, true),  // 5x: not a scale error
                       estimate("C_Y_delta_a", p.C_Y_delta_a, p.C_Y_delta_a, false),
                       estimate("C_n_delta_a", p.C_n_delta_a, p.C_n_delta_a, false),
                       estimate("C_n_delta_r", p.C_n_delta_r, p.C_n_delta_r, false),  // the reference not identified
                       estimate("C_ell_delta_r", p.C_ell_delta_r, p.C_ell_delta_r, false)};
  const ScaledPrior s = scaled_prior(pass, prior);
  REQUIRE(s.scaled.size() == 2);
  CHECK(s.scaled[0].held == "C_L_delta_e");
  CHECK(s.scaled[0].reference == "C_m_delta_e");
  CHECK(s.scaled[0].ratio == doctest::Approx(1.5));
  CHECK(s.scaled[0].given == p.C_L_delta_e);
  CHECK(s.prior.aero.C_L_delta_e == doctest::Approx(1.5 * p.C_L_delta_e));
  CHECK(s.scaled[1].held == "C_L_q");
  CHECK(s.prior.aero.C_L_q == doctest::Approx(0.7 * p.C_L_q));
  CHECK(s.prior.aero.C_Y_delta_a == p.C_Y_delta_a);
  CHECK(s.prior.aero.C_n_delta_a == p.C_n_delta_a);
  CHECK(s.prior.aero.C_ell_delta_r == p.C_ell_delta_r);
  CHECK(s.prior.aero.C_m_delta_e == p.C_m_delta_e);  // the reference itself is the flight's to identify
  // a reference whose sign flipped (ratio < 0), or whose prior is 0, moves nothing
  pass.coefficients[0].estimate = -p.C_m_delta_e;
  pass.coefficients[2].identified = false;
  CHECK(scaled_prior(pass, prior).scaled.empty());
  pass.coefficients[0].prior = 0.0;
  CHECK(scaled_prior(pass, prior).scaled.empty());
}

TEST_CASE("restore_prior: the prior the user gave, and a note and a notes line saying where the held term went") {
  const Aircraft prior = load_aircraft(kAerosonde);
  const double given = prior.aero.C_Y_delta_a, moved = 1.6 * given;
  SysidResult r;
  r.coefficients = {estimate("C_Y_delta_a", moved, moved, false), estimate("C_ell_delta_a", 0.2, 0.3, true)};
  r.notes = {"C_Y_delta_a: not identifiable: poorly determined: 1 +- 9; the prior 0.072 kept", "C_ell_delta_a: something else"};
  r.held_scaled = {{"C_Y_delta_a", "C_ell_delta_a", 1.6, given, "scaled with C_ell_delta_a (x1.600) to 0.072"}};
  restore_prior(r);
  CHECK(r.coefficients[0].prior == given);
  CHECK(r.coefficients[0].estimate == moved);
  CHECK(r.coefficients[0].note == "poorly determined: 1 +- 9; scaled with C_ell_delta_a (x1.600) to 0.072");
  CHECK(r.notes[0] == "C_Y_delta_a: not identifiable: poorly determined: 1 +- 9; scaled with C_ell_delta_a (x1.600) to 0.072");
  CHECK(r.notes[1] == "C_ell_delta_a: something else");
  CHECK(r.coefficients[1].prior == 0.2);
  // a moved term the pass on the moved prior identified: the given prior back, the flight's estimate and an empty note kept
  r.coefficients.push_back(estimate("C_n_delta_a", 1.6 * -0.01, -0.012, true));
  r.held_scaled.push_back({"C_n_delta_a", "C_ell_delta_a", 1.6, -0.01, "scaled with C_ell_delta_a (x1.600) to -0.016"});
  restore_prior(r);
  CHECK(r.coefficients[2].prior == -0.01);
  CHECK(r.coefficients[2].estimate == -0.012);
  CHECK(r.coefficients[2].note.empty());
  CHECK(r.notes.size() == 2);
}

TEST_CASE("format_sysid_table: a held term moved with its surface says \"prior scaled\", one left at the prior \"prior kept\"") {
  SysidResult r;
  r.coefficients = {estimate("C_Y_delta_a", 0.045, 0.072, false), estimate("C_L_q", 4.77, 4.77, false),
                    estimate("C_n_delta_a", -0.01, -0.012, true)};
  r.held_scaled = {{"C_Y_delta_a", "C_ell_delta_a", 1.6, 0.045, "scaled with C_ell_delta_a (x1.600) to 0.072"},
                   {"C_n_delta_a", "C_ell_delta_a", 1.6, -0.01, "scaled with C_ell_delta_a (x1.600) to -0.016"}};
  const std::string table = format_sysid_table(r);
  auto line = [&](const std::string& name) {
    const std::size_t at = table.find(name + " ");
    REQUIRE(at != std::string::npos);
    return table.substr(at, table.find('\n', at) - at);
  };
  CHECK(line("C_Y_delta_a").find("prior scaled: poorly determined") != std::string::npos);
  CHECK(line("C_L_q").find("prior kept: poorly determined") != std::string::npos);
  CHECK(line("C_n_delta_a").find("prior") == std::string::npos);  // identified: its method, not a prior's
}
