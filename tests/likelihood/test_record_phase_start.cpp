// The start of a likelihood fit with one harmonic phase per record (record_phase_start.hpp): a
// forcing too weak for one record's own moment fit (amplitude 0.08 on the bistable Duffing, 16
// records of 200 time units at Δt 0.05, phases spread over the circle) — most records' own fits
// land on noise peaks, and the median of their frequencies is none of them (issue 13's loop study:
// the per-record refit from the medians failed in 10 of 10 seeds, ω 0.97–11.5 against 0.9). The
// start scores the candidate frequencies by the likelihood with the phases scanned: the
// frequency it picks must be the truth's, and the fit from it must recover amplitude and ω.
// (From the medians alone — the former start — this case fails: start ω 7.8, the fit elsewhere.)
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "likelihood_fixtures.hpp"
#include "stat_bounds.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/likelihood/record_phase_start.hpp"
#include "vehs/likelihood/refine.hpp"

using namespace vehs;
using namespace vehs_lik_test;

TEST_CASE("per-record phases: the start finds a forcing the records' own fits miss", "[likelihood][record_phases]") {
  const int R = 16;
  Model truth = bistable();
  Effect h;
  h.id = EffectId::HarmonicForcing;
  h.params = {{"amplitude", 0.08}, {"omega", 0.9}, {"phase", 0.0}};
  truth.effects = {h};
  std::mt19937_64 g(vehs_test::seed(2024));
  std::uniform_real_distribution<double> phase(-M_PI, M_PI);
  Dataset d;
  for (int r = 0; r < R; ++r) {
    Model m = truth;
    m.effects[0].params["phase"] = phase(g);
    d.append(simulate(m, 0.05, 1, 200.0, vehs_test::seed(7100 + std::uint64_t(r)), 0.0, 20));
  }
  identify::Options io;
  io.drift_library = {Term::monomial(1), Term::monomial(3), Term::monomial(0, 1)};
  io.diffusion_library = {Term::monomial(0)};
  Effect forcing;
  forcing.id = EffectId::HarmonicForcing;
  io.effects = {forcing};
  likelihood::ObservedModel start{identify::identify(d, io).model, 0.0, {}};
  std::vector<double> own;  // the records' own frequencies (for the message)
  likelihood::start_record_phases(start, d, [&](const Dataset& one) {
    const Model m = identify::identify(one, io).model;
    own.push_back(m.find_effect(EffectId::HarmonicForcing)->params.at("omega"));
    return m;
  });
  std::sort(own.begin(), own.end());
  const double omega0 = start.model.find_effect(EffectId::HarmonicForcing)->params.at("omega");
  INFO("own-record frequencies from " << own.front() << " to " << own.back() << ", median "
                                      << own[own.size() / 2] << "; start " << omega0);
  // the likelihood's side lobes in ω are 2π/T_record = 0.031 apart: within 3 % is the main lobe
  vehs_test::tally("start omega", omega0 / 0.9 - 1.0);
  CHECK(std::abs(omega0 / 0.9 - 1.0) <= 0.03);
  likelihood::RefineOptions o;
  o.per_record_phase = true;
  const likelihood::Result r = likelihood::refine(start, d, o);
  INFO(r.summary.FullReport());
  // amplitude and ω against their SEs. Over 60 seed shifts (`JOBS=2 scripts/seed-study.sh 60
  // build/tests/test_likelihood "[record_phases]"`): ω's z −0.17 ± 0.12, sd 0.94 (max |z| 2.6) —
  // checked at z_bound(2) (normal, 1e-4 with the amplitude's); the amplitude's z +0.61 ± 0.13,
  // sd 1.04 (max 3.1): a phase free per record takes some noise as forcing (+4 % at 16 records), so
  // its check is |z| ≤ 5, 3.9 measured sd above that mean (≈ 5e-5). The start's ω within 2.0 % of
  // the truth in 60 of 60 (sd 0.68 %; 3 % is 4.4 sd, ≈ 1e-5; before the periodogram's lines were
  // candidates, 1 of 60 missed: no record's own fit came near 0.9). Not checked: 15 % of the
  // amplitude — its SE is 6 % at this size, a 2.4-sd check (1 of 30 failed it).
  for (const auto& [name, value] : std::map<std::string, double>{{"harmonic_forcing.amplitude", 0.08},
                                                                {"harmonic_forcing.omega", 0.9}}) {
    const int k = r.find(name);
    REQUIRE(k >= 0);
    const double est = r.values[std::size_t(k)], se = r.stderrs[std::size_t(k)];
    INFO(name << " " << est << " +- " << se << " (truth " << value << ")");
    vehs_test::tally(name, (est - value) / se, est / value - 1.0);
    CHECK(std::abs(est - value) <= (name == "harmonic_forcing.omega" ? z_bound(2) : 5.0) * se);
  }
}
