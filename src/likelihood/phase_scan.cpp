#include "vehs/likelihood/detail/phase_scan.hpp"

#include <cmath>
#include <vector>

#include "vehs/likelihood/detail/evaluator.hpp"

namespace vehs::likelihood::detail {

double scan_record_phases(ObservedModel& start, const Dataset& data, const FilterOptions& filter,
                          const FitChoice& choice) {
  constexpr int kPhaseGrid = 12;
  const Parameterization p(start, choice, data.records.size(), "likelihood");
  const Evaluator ev(p, data, filter, "likelihood");
  const std::size_t R = data.records.size();
  std::vector<double> theta = p.initial(), per_record, best(R, -INFINITY), best_phase(R);
  for (std::size_t r = 0; r < R; ++r) best_phase[r] = theta[p.phase_index(r)];
  const std::vector<double> given = best_phase;
  for (int j = 0; j < kPhaseGrid; ++j) {
    for (std::size_t r = 0; r < R; ++r) theta[p.phase_index(r)] = given[r] + 2.0 * M_PI * j / kPhaseGrid;
    if (!ev.record_values(theta.data(), per_record, nullptr)) continue;
    for (std::size_t r = 0; r < R; ++r)
      if (per_record[r] > best[r]) {
        best[r] = per_record[r];
        best_phase[r] = std::remainder(theta[p.phase_index(r)], 2.0 * M_PI);
      }
  }
  start.record_phases = best_phase;
  double total = 0.0;
  for (double b : best) total += b;
  return total;
}

}  // namespace vehs::likelihood::detail
