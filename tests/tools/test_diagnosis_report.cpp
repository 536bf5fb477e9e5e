// The diagnosis report's structure (tools/diagnosis_report.hpp) on a hand-made result: what a
// reader sees first and in which order, independent of a diagnose run.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "../diagnose/diagnose_fixtures.hpp"
#include "read_text.hpp"
#include "tools/diagnosis_report.hpp"

namespace fs = std::filesystem;

namespace {

using vehs_test::slurp;

/// An inadequate result whose held-out split was set aside with a huge z on one effect, while a
/// score test claims another (the issue's piezo rig: electromechanical_coupling z 61.5 set aside).
vehs::diagnose::Result set_aside_result() {
  vehs::diagnose::Result r;
  r.verdict = vehs::diagnose::Verdict::Inadequate;
  r.suspects.set_aside = "the model was fitted by the likelihood";
  vehs::diagnose::Suspect coupling;
  coupling.effect = "electromechanical_coupling";
  coupling.z = 61.5, coupling.evidence = 900.0;
  vehs::diagnose::Suspect quadratic;
  quadratic.effect = "quadratic_damping";
  quadratic.z = 2.0, quadratic.evidence = 3.0;
  r.suspects.ranked = {coupling, quadratic};
  vehs::diagnose::ScoreSuspect stop, friction;
  stop.effect = "impact_stop", stop.z = 1.1, stop.p_value = 0.3;
  friction.effect = "coulomb_friction", friction.z = 9.0, friction.p_value = 1e-19, friction.significant = true;
  friction.add = R"({"effects": [{"name": "coulomb_friction"}]})";
  r.score_suspects.ranked = {stop, friction};  // the report orders them: claimed first
  return r;
}

}  // namespace

TEST_CASE("the report's suspects chart puts the claim first and set-aside evidence apart", "[report][suspects]") {
  const fs::path dir = fs::temp_directory_path() / "vehs_diagnosis_report_order";
  fs::remove_all(dir);
  vehs::tools::Report report(dir.string(), "order");
  const vehs::Model model = diag_test::bistable();
  vehs::tools::add_diagnosis_to_report(report, set_aside_result(), "m", {}, "", nlohmann::json::object(), {}, &model);
  const std::string html = slurp(report.write_html());
  // the chart's data: the claimed score-test suspect first, the set-aside effect not in it
  const std::string chart = slurp(dir / "suspects.csv");
  const std::string first_row = chart.substr(chart.find('\n') + 1);
  CHECK(first_row.rfind("coulomb_friction,", 0) == 0);
  CHECK(chart.find("electromechanical_coupling") == std::string::npos);
  // the set-aside evidence is a section of its own, after the claims
  const auto claims = html.find("<h2>Suspects: effects the model may be missing</h2>");
  const auto aside = html.find("<h2>Set aside: held-out suspects");
  REQUIRE(claims != std::string::npos);
  REQUIRE(aside != std::string::npos);
  CHECK(claims < aside);
  CHECK(html.find("electromechanical_coupling") > aside);
  // the top card comes first and holds the verdict, the next step and the parameters
  CHECK(html.find("<section id=\"top-card\" class=\"card\">") == html.find("<section"));
  CHECK(html.find("Verdict: INADEQUATE") < html.find("<h2>Verdict: the components</h2>"));
  CHECK(html.find("<th>standard error</th>") < claims);
  // the score-test table is narrow: no test-statistic or config-fragment columns
  CHECK(html.find("<th>test</th>") == std::string::npos);
}

TEST_CASE("an adequate model's report has no failure section", "[report]") {
  const fs::path dir = fs::temp_directory_path() / "vehs_diagnosis_report_adequate";
  fs::remove_all(dir);
  vehs::tools::Report report(dir.string(), "adequate");
  vehs::diagnose::Result r;
  r.verdict = vehs::diagnose::Verdict::Adequate;
  const vehs::Model model = diag_test::bistable();
  vehs::tools::add_diagnosis_to_report(report, r, "m", {}, "", nlohmann::json::object(), {}, &model);
  const std::string html = slurp(report.write_html());
  CHECK(html.find("Verdict: ADEQUATE") != std::string::npos);
  CHECK(html.find("Where the model fails") == std::string::npos);
}
