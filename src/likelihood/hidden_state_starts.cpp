#include "vehs/likelihood/detail/hidden_state_starts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/data_scales.hpp"
#include "vehs/likelihood/detail/data_share.hpp"
#include "vehs/likelihood/detail/selection.hpp"

namespace vehs::likelihood::detail {

namespace {

/// mean (Δx/Δt)² / Var x (0 when undefined).
double data_omega2(const Dataset& data) {
  const double var = x_variance(data), rate = mean_squared_rate(data);
  return var > 0.0 ? rate / var : 0.0;
}

bool held(const FitChoice& choice, const std::string& name) {
  return std::find(choice.fixed.begin(), choice.fixed.end(), name) != choice.fixed.end();
}

}  // namespace

ObservedModel best_hidden_state_start(const ObservedModel& start, const Dataset& data,
                                      const RefineOptions& o, const FitChoice& choice) {
  const Effect* e = start.model.find_effect(EffectId::ElectromechanicalCoupling);
  if (!e || held(choice, "electromechanical_coupling.coupling") ||
      held(choice, "electromechanical_coupling.lambda"))
    return start;
  const double w2 = data_omega2(data);
  if (!(w2 > 0.0) || !std::isfinite(w2)) return start;
  const double budget = 4.0 * double(o.warm_start_samples);
  const Dataset share = double(data.x.size()) > budget
                            ? warm_start_share(data, budget / double(data.x.size()), choice.per_record_phase)
                            : Dataset{};
  const Dataset& fit_data = share.x.empty() ? data : share;
  RefineOptions so = o;
  so.log = {};
  ObservedModel best = start;
  double best_ll = -std::numeric_limits<double>::infinity();
  double best_lambda = e->param("lambda");
  const double kappa = std::max(e->param("coupling"), 0.1 * w2);
  const double mult[] = {0.1, 1.0};
  for (int c = -1; c < 2; ++c) {
    ObservedModel cand = start;
    if (c >= 0) {
      for (Effect& ce : cand.model.effects)
        if (ce.id == EffectId::ElectromechanicalCoupling)
          ce.params["lambda"] = std::sqrt(w2) * mult[std::size_t(c)], ce.params["coupling"] = kappa;
    }
    try {
      const Result r = fit_support(cand, fit_data, so, choice, false);
      if (std::isfinite(r.log_likelihood) && r.log_likelihood > best_ll) {
        best_ll = r.log_likelihood;
        best = r.model;  // its fit: the final fit starts at this candidate's optimum
        best_lambda = cand.model.find_effect(EffectId::ElectromechanicalCoupling)->param("lambda");
      }
    } catch (const Error&) {
      // this start's fit failed: the others decide
    }
  }
  if (o.log && best_lambda != e->param("lambda")) {
    char line[200];
    std::snprintf(line, sizeof line,
                  "likelihood: electromechanical_coupling started at lambda %.4g (data omega %.4g): its fit "
                  "reached the highest log L of three starts",
                  best_lambda, std::sqrt(w2));
    o.log(line);
  }
  return best;
}

}  // namespace vehs::likelihood::detail
