// FitSummary's reports: what a user reads after vehs::fit.
#include <cmath>
#include <sstream>

#include "vehs/core/detail/format.hpp"
#include "vehs/fit/fit.hpp"

namespace vehs {

namespace {

std::string g(double v, int digits = 6) { return vehs::detail::format_number(v, digits); }

}  // namespace

std::vector<std::string> FitSummary::Warnings() const {
  std::vector<std::string> out;
  if (!input.warning.empty()) out.push_back(input.warning);
  for (const std::string& w : refinement.warnings) out.push_back(w);
  return out;
}

std::string FitSummary::BriefReport() const {
  std::ostringstream s;
  const Model& m = result.model;
  for (const std::string& d : dropped) s << "data: " << d << "\n";
  if (!input.why.empty()) s << "input: " << input.why << "\n";
  if (m.fit)
    s << "moment fit: " << enum_to_string(kEstimatorNames, m.fit->estimator) << " (" << result.report.estimator.reason
      << "), " << m.drift.size() << " drift and " << m.diffusion.size() << " diffusion terms, " << m.effects.size()
      << " effects\n";
  s << "sampling: " << refinement.adequacy.reason << "\n";
  for (const LikelihoodStart& st : refinement.starts)
    s << "likelihood start " << st.name << ": "
      << (std::isfinite(st.log_likelihood) ? "log L " + g(st.log_likelihood, 10) + ", " : std::string()) << st.status
      << "\n";
  if (refinement.result)
    s << refinement.result->summary.BriefReport() << "\nlog L " << g(refinement.result->log_likelihood, 10) << ", BIC "
      << g(refinement.result->bic, 10) << "\n";
  else if (!refinement.failure.empty())
    s << "likelihood: failed (" << refinement.failure << "); the moment fit stands\n";
  else
    s << "likelihood: not used\n";
  for (const std::string& w : Warnings()) s << "warning: " << w << "\n";
  s << "fitted in " << g(seconds, 3) << " s";
  return s.str();
}

}  // namespace vehs
