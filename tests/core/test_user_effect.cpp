// A user's own effect (vehs/core/user_effect.hpp): what makes one valid, its terms, and its
// parameters read back from a model's coefficients.
#include <catch2/catch.hpp>

#include "vehs/core/user_effect.hpp"

using namespace vehs;

namespace {

UserEffect friction() {
  UserEffect e;
  e.name = "directional_friction";
  e.params = {{"Fp", Term::parse("-(y>0)"), false}, {"Fm", Term::parse("(y<0)"), false}, {"q", Term::parse("y^2"), true}};
  return e;
}

}  // namespace

TEST_CASE("a user effect is valid with a name, unique parameters and terms", "[core][user]") {
  CHECK(friction().invalid_reason().empty());
  UserEffect e = friction();
  e.name.clear();
  CHECK(e.invalid_reason().find("non-empty 'name'") != std::string::npos);
  e = friction();
  e.name = "quadratic_damping";
  CHECK(e.invalid_reason().find("is a catalogue effect") != std::string::npos);
  e = friction();
  e.params.clear();
  CHECK(e.invalid_reason().find("at least one parameter") != std::string::npos);
  e = friction();
  e.params.push_back({"Fp", Term::parse("x"), false});
  CHECK(e.invalid_reason().find("'Fp' is given twice") != std::string::npos);
  e = friction();
  e.params.push_back({"other", Term::parse("(y<0)"), false});
  CHECK(e.invalid_reason().find("belongs to two parameters") != std::string::npos);
  e = friction();
  e.params.push_back({"same_term_in_diffusion", Term::parse("x^2"), true});
  e.params.push_back({"same_term_in_drift", Term::parse("x^2"), false});
  CHECK(e.invalid_reason().empty());
  e = friction();
  e.params.push_back({"drive", Term::parse("u"), true});
  CHECK(e.invalid_reason().find("not allowed in the diffusion") != std::string::npos);
}

TEST_CASE("a user effect's parameters are its terms' coefficients", "[core][user]") {
  const UserEffect e = friction();
  const EffectTerms t = e.unit_terms();
  REQUIRE(t.drift.size() == 2);
  REQUIRE(t.diffusion.size() == 1);
  CHECK(t.drift[0].term == Term::parse("-(y>0)"));
  CHECK(t.drift[0].coef == 1.0);
  Model m;
  m.drift = {{Term::monomial(1), -1.0}, {Term::parse("-(y>0)"), 0.3}, {Term::parse("(y<0)"), 0.2}};
  m.diffusion = {{Term::monomial(0), 0.1}, {Term::monomial(0, 2), 0.05}};
  m.drift_stderr = {{"-(y>0)", 0.01}, {"(y<0)", 0.02}};
  m.diffusion_stderr = {{"y^2", 0.005}};
  const UserEffectFit f = user_effect_fit(m, e);
  CHECK(f.name == "directional_friction");
  CHECK(f.params.at("Fp") == 0.3);
  CHECK(f.params.at("Fm") == 0.2);
  CHECK(f.params.at("q") == 0.05);
  CHECK(f.stderr_.at("Fm") == 0.02);
  CHECK(f.stderr_.at("q") == 0.005);
  m.drift.pop_back();  // a term the model lacks: its parameter is 0, without a standard error
  m.drift_stderr.erase("(y<0)");
  const UserEffectFit g = user_effect_fit(m, e);
  CHECK(g.params.at("Fm") == 0.0);
  CHECK(g.stderr_.count("Fm") == 0);
}
