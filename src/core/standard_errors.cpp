#include "vehs/core/standard_errors.hpp"

#include <algorithm>
#include <cmath>

#include "vehs/core/error.hpp"

namespace vehs {

namespace {

/// A parameter's standard-error slot in the model, by its covariance name; null when the
/// model has no such parameter.
double* stderr_slot(Model& m, const std::string& name) {
  auto term_in = [&](const TermList& list, const std::string& term) {
    return std::any_of(list.begin(), list.end(), [&](const TermCoef& tc) { return tc.term.name() == term; });
  };
  auto inner = [&](std::size_t open) { return name.substr(open, name.size() - open - 1); };
  if (name.rfind("drift[", 0) == 0 && name.back() == ']')
    return term_in(m.drift, inner(6)) ? &m.drift_stderr[inner(6)] : nullptr;
  if (name.rfind("diffusion[", 0) == 0 && name.back() == ']')
    return term_in(m.diffusion, inner(10)) ? &m.diffusion_stderr[inner(10)] : nullptr;
  const auto dot = name.find('.');
  if (dot == std::string::npos) return nullptr;
  for (Effect& e : m.effects)
    if (e.name() == name.substr(0, dot) && e.params.count(name.substr(dot + 1)))
      return &e.stderr_[name.substr(dot + 1)];
  return nullptr;
}

/// Every standard error of the model by its covariance name.
std::vector<std::pair<std::string, double>> listed_stderrs(const Model& m) {
  std::vector<std::pair<std::string, double>> out;
  for (const auto& tc : m.drift)
    if (auto it = m.drift_stderr.find(tc.term.name()); it != m.drift_stderr.end())
      out.emplace_back("drift[" + it->first + "]", it->second);
  for (const auto& tc : m.diffusion)
    if (auto it = m.diffusion_stderr.find(tc.term.name()); it != m.diffusion_stderr.end())
      out.emplace_back("diffusion[" + it->first + "]", it->second);
  for (const Effect& e : m.effects)
    for (const auto& [param, se] : e.stderr_) out.emplace_back(e.name() + "." + param, se);
  return out;
}

/// The covariance with one more parameter, uncorrelated with the others.
void add_uncorrelated(ParameterCovariance& c, const std::string& name, double variance) {
  const std::size_t n = c.size();
  std::vector<double> grown((n + 1) * (n + 1), 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) grown[i * (n + 1) + j] = c(i, j);
  grown[n * (n + 1) + n] = variance;
  c.names.push_back(name);
  c.matrix = std::move(grown);
}

}  // namespace

void standard_errors_from_covariance(Model& m, const std::string& where) {
  if (m.covariance.empty()) return;
  for (const auto& [name, se] : listed_stderrs(m))
    if (m.covariance.index_of(name) == m.covariance.size()) add_uncorrelated(m.covariance, name, se * se);
  if (const std::string why = m.covariance.invalid_reason(); !why.empty())
    throw Error(where + ": the covariance of the estimates is not valid: " + why);
  for (std::size_t i = 0; i < m.covariance.size(); ++i) {
    double* slot = stderr_slot(m, m.covariance.names[i]);
    if (!slot)
      throw Error(where + ": the covariance of the estimates lists '" + m.covariance.names[i] +
                  "', which is not a parameter of the model");
    *slot = std::sqrt(m.covariance(i, i));
  }
}

}  // namespace vehs
