// A user's own effect (vehs/core/user_effect.hpp) through vehs::fit: friction that differs by
// direction, written as a named set of parameters on top of a baseline with linear damping —
// Coulomb friction per direction and the extra viscous damping when moving backward — in
// physical units, coarse sampling; records from directional_friction.hpp (not vehs's simulator).
#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <string>

#include "vehs/core/error.hpp"
#include "vehs/fit/fit.hpp"

#include "directional_friction.hpp"

namespace {

vehs::UserEffect directional_effect() {
  vehs::UserEffect e;
  e.name = "directional_friction";
  e.params = {{"Fp", vehs::Term::parse("-(y>0)"), false},
              {"Fm", vehs::Term::parse("(y<0)"), false},
              {"dc", vehs::Term::parse("-y*(y<0)"), false}};
  return e;
}

vehs::FitOptions baseline_options() {
  vehs::FitOptions o;
  o.moment.drift_library = {vehs::Term::monomial(1), vehs::Term::monomial(0, 1)};
  o.moment.diffusion_library = {vehs::Term::monomial(0)};
  o.libraries_given = {true, true};
  return o;
}

}  // namespace

TEST_CASE("fit - a user effect's parameters with standard errors in physical units", "[fit][user]") {
  const vehs::Dataset data = directional::directional_friction(20000, 17, 5e-3, 1e-7);
  vehs::FitOptions o = baseline_options();
  o.moment.user_effects = {directional_effect()};
  o.moment.sparsity = vehs::identify::Sparsity::None;  // the baseline's damping stays: dc is the difference
  const vehs::FitSummary fit = vehs::fit(data, o);
  INFO(fit.BriefReport());
  const auto& ups = fit.result.report.user_effect_params;
  REQUIRE(ups.size() == 1);
  CHECK(ups[0].name == "directional_friction");
  const directional::Truth p;
  // each within 4.5 SE: a false failure has probability 4 × 6.8e-6 < 1e-4 for a consistent fit
  const std::map<std::string, double> truth{{"Fp", p.Fp}, {"Fm", p.Fm}, {"dc", p.cm - p.cp}};
  for (const auto& [name, value] : truth) {
    REQUIRE(ups[0].params.count(name) == 1);
    REQUIRE(ups[0].stderr_.count(name) == 1);
    CAPTURE(name, value, ups[0].params.at(name), ups[0].stderr_.at(name));
    CHECK(std::abs(ups[0].params.at(name) - value) < 4.5 * ups[0].stderr_.at(name));
  }
  const vehs::Model& m = fit.model();
  CHECK(std::abs(m.drift_coef("y") + p.cp) < 4.5 * m.drift_stderr.at("y"));
}

TEST_CASE("fit - a user effect's terms survive both selections", "[fit][user]") {
  // 1 % sensor noise: the likelihood refines with its selection on (the default); a user effect
  // whose parameter is 0 in the data must stay in the model, as a requested catalogue effect does
  const vehs::Dataset data = directional::directional_friction(1500, 5, 5e-3, 1e-5);
  vehs::FitOptions o = baseline_options();
  vehs::UserEffect none;
  none.name = "cubic_spring";
  none.params = {{"k3", vehs::Term::parse("-x^3"), false}};
  o.moment.user_effects = {none};
  o.moment.effects = {vehs::Effect{vehs::EffectId::QuadraticDamping, {}, {}}};
  const vehs::FitSummary fit = vehs::fit(data, o);
  INFO(fit.BriefReport());
  REQUIRE(fit.refinement.result.has_value());
  REQUIRE(o.likelihood.options.select);
  const vehs::Model& m = fit.model();
  CHECK(m.drift_coef("-x^3") != 0.0);
  CHECK(m.drift_coef("y*|y|") != 0.0);
  REQUIRE(fit.result.report.user_effect_params.size() == 1);
  CHECK(fit.result.report.user_effect_params[0].stderr_.count("k3") == 1);
}

TEST_CASE("fit - a user effect that is not valid is refused with its name", "[fit][user]") {
  const vehs::Dataset data = directional::directional_friction(1000, 5, 5e-3, 1e-7);
  vehs::FitOptions o = baseline_options();
  vehs::UserEffect e = directional_effect();
  e.params.push_back({"Fp", vehs::Term::parse("x^2"), false});
  o.moment.user_effects = {e};
  CHECK_THROWS_WITH(vehs::fit(data, o), Catch::Contains("directional_friction") && Catch::Contains("'Fp' is given twice"));
  e = directional_effect();
  e.name = "coulomb_friction";
  o.moment.user_effects = {e};
  CHECK_THROWS_WITH(vehs::fit(data, o), Catch::Contains("is a catalogue effect"));
}

TEST_CASE("fit - a user effect on a noisy coarse record with the defaults", "[fit][user]") {
  // 1 % sensor noise at 40 samples per period on 20 000 samples: the sampling rule must read a
  // sensor on a continuous process (it read an explicit scheme, and the forward fit put Fp and Fm
  // 9–10 SE off); every parameter within 4.5 SE (false failure ≤ 5 × 6.8e-6 < 1e-4)
  const vehs::Dataset data = directional::directional_friction(20000, 23, 5e-3, 1e-5);
  vehs::FitOptions o = baseline_options();
  o.moment.user_effects = {directional_effect()};
  const vehs::FitSummary fit = vehs::fit(data, o);
  INFO(fit.BriefReport());
  CHECK(fit.result.model.fit->estimator != vehs::Estimator::Forward);
  const auto& u = fit.result.report.user_effect_params.at(0);
  const directional::Truth p;
  const vehs::Model& m = fit.model();
  // the selection may remove the baseline's weak damping y (cp 2 1/s); dc is then checked no more
  const bool damping = m.drift_coef("y") != 0.0;
  std::map<std::string, double> truth{{"Fp", p.Fp}, {"Fm", p.Fm}};
  if (damping) truth["dc"] = p.cm - p.cp;
  for (const auto& [name, value] : truth) {
    CAPTURE(name, value, u.params.at(name), u.stderr_.at(name));
    CHECK(std::abs(u.params.at(name) - value) < 4.5 * u.stderr_.at(name));
  }
  CHECK(std::abs(m.drift_coef("x") + p.k) < 4.5 * m.drift_stderr.at("x"));
  if (damping) CHECK(std::abs(m.drift_coef("y") + p.cp) < 4.5 * m.drift_stderr.at("y"));
}

TEST_CASE("fit - an expression small in physical units fits as the grammar's term", "[fit][user]") {
  // "-x^3" in metres is about 1e-9: fitted in internal units as a term of size O(1) (before, its
  // standard error came out "not positive"); the grammar's "x^3" estimate and SE, up to the
  // finite-difference derivatives of an expression in the moment fit's corrections (0.011 SE)
  const vehs::Dataset data = directional::directional_friction(4000, 3, 5e-3, 1e-7);
  auto fitted = [&](const char* cubic) {
    vehs::FitOptions o = baseline_options();
    o.moment.drift_library.push_back(vehs::Term::parse(cubic));
    o.moment.sparsity = vehs::identify::Sparsity::None;
    o.likelihood.use = vehs::LikelihoodUse::Never;
    const vehs::Model m = vehs::fit(data, o).model();
    return std::make_pair(m.drift_coef(cubic), m.drift_stderr.at(cubic));
  };
  const auto [expression, expression_se] = fitted("-x^3");
  const auto [grammar, grammar_se] = fitted("x^3");
  CAPTURE(expression, expression_se, grammar, grammar_se);
  REQUIRE(std::isfinite(expression_se));
  CHECK(std::abs(expression + grammar) < 0.05 * grammar_se);
  CHECK(expression_se == Approx(grammar_se).epsilon(1e-4));
}

TEST_CASE("fit - an expression that is not finite on the data names the term and the line", "[fit][user]") {
  vehs::Dataset data = directional::directional_friction(1000, 3, 5e-3, 1e-7);
  data.records[0].first_line = 2;
  vehs::FitOptions o = baseline_options();
  o.moment.drift_library.push_back(vehs::Term::parse("log(y)"));  // y < 0 on half the samples
  try {
    (void)vehs::fit(data, o);
    FAIL("no error");
  } catch (const vehs::Error& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find("rig.csv: line ") != std::string::npos);
    CHECK(what.find("the drift term 'log(y)' is not finite") != std::string::npos);
  }
}
