// The verdict of a diagnosis: inadequate when a component's p-value is below alpha / (available
// components); the score is the sum of the components' excess normalised chi-squares.
#include "comparison.hpp"
#include "vehs/diagnose/distributions.hpp"

namespace vehs::diagnose::detail {

void finish_verdict(Result& res, double alpha) {
  int available = 0;
  for (const auto& c : res.components) available += c.test.available;
  res.threshold = available > 0 ? alpha / available : alpha;
  bool bad = false;
  res.score = 0.0;
  for (const auto& c : res.components)
    if (c.test.available) {
      bad = bad || c.test.p_value < res.threshold;
      res.score += c.test.excess;
      res.score_expected_adequate += chi2_sf(c.test.dof, c.test.dof + 2.0) - chi2_sf(c.test.dof, c.test.dof);
    }
  res.verdict = bad ? Verdict::Inadequate : Verdict::Adequate;
  if (available == 0) res.warnings.push_back("no test could be computed: the verdict rests on nothing");
}

}  // namespace vehs::diagnose::detail
