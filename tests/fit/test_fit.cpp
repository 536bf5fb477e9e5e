// vehs::fit (include/vehs/fit/fit.hpp): options and their validity, the data checks, the input
// column taken into the library, the likelihood's starts and a fit that did not converge said so.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "vehs/core/error.hpp"
#include "vehs/fit/fit.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/sim/simulate.hpp"
#include "fit/driven_record.hpp"

namespace {


vehs::Dataset driven(double dt, std::size_t n, std::uint64_t seed) { return fit_test::driven(dt, n, seed); }

bool has_term(const vehs::Model& m, const char* name) {
  return std::any_of(m.drift.begin(), m.drift.end(), [&](const vehs::TermCoef& t) { return t.term.name() == name; });
}

}  // namespace

TEST_CASE("fit options - the defaults are valid and an invalid option names itself") {
  vehs::FitOptions o;
  std::string why;
  CHECK(o.IsValid(&why));
  CHECK(why.empty());
  o.likelihood.options.max_rounds = 0;
  CHECK_FALSE(o.IsValid(&why));
  CHECK(why.find("max_rounds") != std::string::npos);
  CHECK_THROWS_WITH(vehs::fit(vehs::Dataset{}, o), Catch::Contains("max_rounds"));
}

TEST_CASE("fit - the data checks run before the fit under each rule") {
  vehs::Dataset d = driven(0.1, 3000, 3);
  d.x[1500] += 50.0;  // one glitch sample
  vehs::FitOptions o;
  CHECK_THROWS_WITH(vehs::fit(d, o), Catch::Contains("isolated glitch sample") && Catch::Contains("'glitches'"));
  o.checks.glitches = vehs::CheckRule::Drop;
  o.likelihood.use = vehs::LikelihoodUse::Never;
  const vehs::FitSummary s = vehs::fit(d, o);
  REQUIRE(s.dropped.size() == 1);
  CHECK(s.dropped[0].find("dropped 1 isolated glitch sample") == 0);
  CHECK(s.BriefReport().find("data: dropped 1 isolated glitch sample") != std::string::npos);
  const vehs::CheckedData kept = vehs::check_data(d, {vehs::CheckRule::Keep, vehs::CheckRule::Keep});
  CHECK(kept.dropped.empty());
  CHECK(kept.data.total_samples() == d.total_samples());
}

TEST_CASE("fit - an input column enters the default library and a given library without it is warned of") {
  const vehs::Dataset d = driven(0.1, 4000, 5);
  vehs::FitOptions o;
  o.likelihood.use = vehs::LikelihoodUse::Never;
  const vehs::FitSummary s = vehs::fit(d, o);
  CHECK(s.input.added);
  CHECK(has_term(s.model(), "u"));
  CHECK(s.Warnings().empty());
  o.moment.drift_library = {vehs::Term::monomial(1, 0), vehs::Term::monomial(0, 1)};
  o.libraries_given.drift = true;
  const vehs::FitSummary w = vehs::fit(d, o);
  CHECK_FALSE(has_term(w.model(), "u"));
  REQUIRE(w.Warnings().size() == 1);
  CHECK(w.Warnings()[0].find("is not used") != std::string::npos);
}

TEST_CASE("fit - the likelihood starts from every moment fit and keeps the highest") {
  const vehs::Dataset d = driven(0.5, 3000, 7);  // coarse: the sampling cannot vouch for the moment fit
  vehs::FitOptions o;
  if (std::getenv("VEHS_TEST_LOG")) o.log = [](const std::string& l) { std::fprintf(stderr, "%s\n", l.c_str()); };
  const vehs::FitSummary s = vehs::fit(d, o);
  REQUIRE(s.refinement.result);
  REQUIRE(s.refinement.starts.size() >= 2);
  double best = -INFINITY;
  std::string chosen;
  for (const vehs::LikelihoodStart& st : s.refinement.starts)
    if (std::isfinite(st.log_likelihood) && st.log_likelihood > best) best = st.log_likelihood, chosen = st.status;
  CHECK(chosen == "chosen");
  CHECK(s.BriefReport().find("likelihood start") != std::string::npos);
  // stderr = sqrt(diag(covariance)): one uncertainty
  const vehs::Model& m = s.model();
  REQUIRE_FALSE(m.covariance.empty());
  for (const vehs::TermCoef& t : m.drift) {
    const std::size_t k = m.covariance.index_of("drift[" + t.term.name() + "]");
    REQUIRE(k < m.covariance.size());
    CHECK(m.drift_stderr.at(t.term.name()) == std::sqrt(m.covariance(k, k)));
  }
}

TEST_CASE("fit - a likelihood that did not converge is never silent") {
  const vehs::Dataset d = driven(0.5, 3000, 9);
  vehs::FitOptions o;
  o.likelihood.use = vehs::LikelihoodUse::Always;
  o.likelihood.options.max_rounds = 1;
  o.likelihood.options.max_iterations = 1;
  o.likelihood.options.step_tolerance = 1e-12;
  o.likelihood.options.select = false;
  o.likelihood_starts = false;
  const vehs::FitSummary s = vehs::fit(d, o);
  REQUIRE(s.refinement.result);
  CHECK_FALSE(s.refinement.result->summary.converged);
  const std::vector<std::string> w = s.Warnings();
  CHECK(std::any_of(w.begin(), w.end(), [](const std::string& l) { return l.find("did not converge") != std::string::npos; }));
}

TEST_CASE("fit - a smooth input held by a DAC is read as held by the likelihood - not by its spectrum") {
  // the AR(1) input's spectrum reads band-limited; held over each interval it is a staircase: read
  // by the spectrum alone β, k and the gain came out 7-11 SE off. Bound 4.5 SE on each of three
  // parameters: false-failure probability 3 x 6.8e-6 = 2e-5 for a calibrated fit.
  const vehs::Dataset d = driven(0.5, 3000, 7);
  const vehs::FitSummary s = vehs::fit(d, vehs::FitOptions{});
  REQUIRE(s.refinement.result);
  REQUIRE(s.model().fit);
  CHECK(s.model().fit->input == vehs::InputInterpolation::ZeroOrderHold);
  CHECK(s.refinement.input_reason.find("zoh by the likelihood") == 0);
  CHECK(s.refinement.input_reason.find("band_limited") != std::string::npos);
  const vehs::Model& m = s.model();
  for (const auto& [term, truth] : std::vector<std::pair<std::string, double>>{{"x", -1.0}, {"y", -0.2}, {"u", 0.5}}) {
    INFO(term << ": " << m.drift_coef(term) << " +- " << m.drift_stderr.at(term) << " (truth " << truth << ")");
    CHECK(std::abs(m.drift_coef(term) - truth) < 4.5 * m.drift_stderr.at(term));
  }
}

TEST_CASE("fit - folds that leave fewer than 100 samples each are refused with one line") {
  const vehs::Dataset d = driven(0.1, 600, 3);
  vehs::FitOptions o;
  o.likelihood.use = vehs::LikelihoodUse::Never;
  o.moment.folds = 10;
  o.folds_given = true;
  CHECK_THROWS_WITH(vehs::fit(d, o), Catch::Contains("folds = 10 leaves fewer than 100 samples per fold"));
  o.folds_given = false;  // the default is fitted to the data: 6 folds
  CHECK(vehs::fit_folds(o, d.total_samples()) == 6);
  CHECK_NOTHROW(vehs::fit(d, o));
}
