#include "vehs/likelihood/filter.hpp"

#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/evaluator.hpp"

namespace vehs::likelihood {

std::string FilterOptions::invalid_reason() const {
  if (substeps < 0) return "substeps must be >= 0 (0: automatic)";
  if (substeps > 100000) return "substeps must be <= 100000";
  if (block_samples < 16) return "block_samples must be >= 16";
  if (threads < 0) return "threads must be >= 0 (0: all)";
  return "";
}

namespace {

detail::Parameterization evaluation_parameters(const ObservedModel& model, const Dataset& data) {
  detail::FitChoice choice;
  choice.fit_measurement_noise = false;
  choice.per_record_phase = !model.record_phases.empty();
  return detail::Parameterization(model, choice, data.records.size(), "likelihood");
}

template <class Fn>
auto with_evaluator(const ObservedModel& model, const Dataset& data, const FilterOptions& options,
                    Fn fn) {
  validate_model(model.model, "likelihood: model");
  const auto p = evaluation_parameters(model, data);
  const detail::Evaluator ev(p, data, options, "likelihood");
  return fn(ev, p.initial().data());
}

}  // namespace

LikelihoodValue log_likelihood(const ObservedModel& model, const Dataset& data,
                               const FilterOptions& options) {
  return with_evaluator(model, data, options, [](const detail::Evaluator& ev, const double* theta) {
    LikelihoodValue v;
    detail::EvaluationFailure f;
    if (!ev.value(theta, v.log_likelihood, &f)) throw FilterDiverged(ev.message(f));
    v.observations = ev.observations();
    v.substeps = ev.settings().substeps;
    v.blocks = ev.blocks().size();
    return v;
  });
}

FilterTrace filter_trace(const ObservedModel& model, const Dataset& data,
                         const FilterOptions& options) {
  return with_evaluator(model, data, options, [](const detail::Evaluator& ev, const double* theta) {
    FilterTrace t;
    detail::EvaluationFailure f;
    if (!ev.trace(theta, t, &f)) throw FilterDiverged(ev.message(f));
    return t;
  });
}

}  // namespace vehs::likelihood
