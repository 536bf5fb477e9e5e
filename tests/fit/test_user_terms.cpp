// A force the catalogue lacks, fitted through users' expression terms: friction that differs by
// direction (Coulomb and viscous per direction, the published ball-screw case), in physical
// units, sampled coarsely; the generator (Euler–Maruyama on 50
// substeps of each recorded interval) is not vehs's simulator.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <utility>

#include "vehs/fit/fit.hpp"

#include "directional_friction.hpp"

using directional::directional_friction;
using directional::Truth;

TEST_CASE("fit - friction per direction as user terms in physical units", "[fit][user]") {
  // x about 1 mm rms, sensor noise 0.01 % of that, 40 samples per period: the moment fit's
  // ground (at 1 % sensor noise it is biased and the likelihood is needed, see below)
  const vehs::Dataset data = directional_friction(20000, 17, 5e-3, 1e-7);
  vehs::FitOptions o;
  o.moment.drift_library = {vehs::Term::monomial(1), vehs::Term::parse("(y>0)"), vehs::Term::parse("(y<0)"),
                            vehs::Term::parse("y*(y>0)"), vehs::Term::parse("y*(y<0)")};
  o.moment.diffusion_library = {vehs::Term::monomial(0)};
  o.libraries_given = {true, true};
  o.moment.sparsity = vehs::identify::Sparsity::None;  // every term of the force is known to be there
  const vehs::FitSummary fit = vehs::fit(data, o);
  INFO(fit.BriefReport());
  const vehs::Model& m = fit.model();
  const Truth p;
  // each within 4.5 SE: a false failure has probability 5 × 6.8e-6 < 1e-4 for a consistent fit
  auto check = [&](const char* term, double truth) {
    CAPTURE(term, truth, m.drift_coef(term), m.drift_stderr.at(term));
    CHECK(std::abs(m.drift_coef(term) - truth) < 4.5 * m.drift_stderr.at(term));
  };
  check("x", -p.k);
  check("(y>0)", -p.Fp);
  check("(y<0)", p.Fm);
  check("y*(y>0)", -p.cp);
  check("y*(y<0)", -p.cm);
}

TEST_CASE("fit - a noisy record with expression terms gets the likelihood by default", "[fit][user]") {
  // 1 % sensor noise: the sampling rule asks for the likelihood, which runs on expression terms
  // as on the catalogue's; the Coulomb terms per direction within 4.5 SE of the truth (a false
  // failure has probability 3 × 6.8e-6 < 1e-4 for a consistent fit)
  const vehs::Dataset data = directional_friction(1500, 5, 5e-3, 1e-5);
  vehs::FitOptions o;
  o.moment.drift_library = {vehs::Term::monomial(1), vehs::Term::parse("(y>0)"), vehs::Term::parse("(y<0)"),
                            vehs::Term::parse("y*(y>0)"), vehs::Term::parse("y*(y<0)")};
  o.moment.diffusion_library = {vehs::Term::monomial(0)};
  o.libraries_given = {true, true};
  o.moment.sparsity = vehs::identify::Sparsity::None;
  const vehs::FitSummary fit = vehs::fit(data, o);
  INFO(fit.BriefReport());
  REQUIRE(fit.refinement.result.has_value());
  const vehs::Model& m = fit.model();
  const Truth p;
  for (const auto& [term, truth] : {std::pair<const char*, double>{"x", -p.k}, {"(y>0)", -p.Fp}, {"(y<0)", p.Fm}}) {
    CAPTURE(term, truth, m.drift_coef(term));
    REQUIRE(m.drift_stderr.count(term) == 1);
    CHECK(std::abs(m.drift_coef(term) - truth) < 4.5 * m.drift_stderr.at(term));
  }
}

TEST_CASE("fit - friction per direction by the likelihood", "[.user_likelihood]") {
  const vehs::Dataset data = directional_friction(std::size_t(std::atof(std::getenv("VEHS_N") ? std::getenv("VEHS_N") : "4000")), 17, 5e-3, 1e-5);
  vehs::FitOptions o;
  o.moment.drift_library = {vehs::Term::monomial(1), vehs::Term::parse("(y>0)"), vehs::Term::parse("(y<0)"),
                            vehs::Term::parse("y*(y>0)"), vehs::Term::parse("y*(y<0)")};
  o.moment.diffusion_library = {vehs::Term::monomial(0)};
  o.libraries_given = {true, true};
  o.likelihood.use = vehs::LikelihoodUse::Always;
  o.log = [](const std::string& s) { std::fprintf(stderr, "%s\n", s.c_str()); };
  const vehs::FitSummary fit = vehs::fit(data, o);
  std::fprintf(stderr, "%s\n", fit.BriefReport().c_str());
  for (const auto& tc : fit.model().drift)
    std::fprintf(stderr, "%s %g +- %g\n", tc.term.name().c_str(), tc.coef, fit.model().drift_stderr.at(tc.term.name()));
}

TEST_CASE("fit - an expression for sign(y) fits as the built-in term by the likelihood", "[fit][user]") {
  // the same force written twice: the filter's quadrature of the expression and the simulated
  // data sets of the bias correction must give the built-in term's estimate (before, the
  // expression's derivative spikes at its jump kicked the Taylor 1.5 simulation, and the
  // correction moved the estimate 4.5 SE instead of 0.8)
  const vehs::Dataset data = directional_friction(1000, 3, 5e-3, 1e-5);
  auto fit_with = [&](const char* friction) {
    vehs::FitOptions o;
    o.moment.drift_library = {vehs::Term::monomial(1), vehs::Term::monomial(0, 1), vehs::Term::parse(friction)};
    o.moment.diffusion_library = {vehs::Term::monomial(0)};
    o.libraries_given = {true, true};
    o.moment.sparsity = vehs::identify::Sparsity::None;
    o.likelihood.use = vehs::LikelihoodUse::Always;
    o.likelihood.options.select = false;
    o.likelihood.options.bias_correction_auto = false;
    o.likelihood.options.bias_correction_datasets = 4;
    return vehs::fit(data, o).model();
  };
  const vehs::Model builtin = fit_with("sign(y)"), user = fit_with("(y>0)-(y<0)");
  for (const auto& [a, b] : {std::pair<const char*, const char*>{"x", "x"}, {"y", "y"}, {"sign(y)", "(y>0)-(y<0)"}}) {
    CAPTURE(a, builtin.drift_coef(a), user.drift_coef(b), builtin.drift_stderr.at(a));
    CHECK(std::abs(builtin.drift_coef(a) - user.drift_coef(b)) < 0.05 * builtin.drift_stderr.at(a));
    CHECK(user.drift_stderr.at(b) == Approx(builtin.drift_stderr.at(a)).epsilon(0.02));
  }
  CHECK(user.diffusion_coef("1") == Approx(builtin.diffusion_coef("1")).epsilon(0.01));
}
