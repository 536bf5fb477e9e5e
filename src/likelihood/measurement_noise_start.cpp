#include "vehs/likelihood/detail/measurement_noise_start.hpp"

#include <cmath>
#include <limits>

#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/data_scales.hpp"
#include "vehs/likelihood/detail/data_share.hpp"

namespace vehs::likelihood::detail {

double measurement_sd_start(const ObservedModel& start, const Dataset& data, const FilterOptions& fo,
                            bool keep_records) {
  const double sd = std::sqrt(x_variance(data));
  if (!(sd > 0.0)) throw Error("likelihood: the records have zero variance");
  constexpr double kBudget = 1e5;
  const Dataset share = double(data.x.size()) > kBudget
                            ? warm_start_share(data, kBudget / double(data.x.size()), keep_records)
                            : Dataset{};
  const Dataset& on = share.x.empty() ? data : share;
  double best = 0.01 * sd, best_ll = -std::numeric_limits<double>::infinity();
  for (double share_of_sd : {0.03, 0.01, 0.003, 0.001, 0.0003, 0.0001}) {
    ObservedModel m = start;
    m.measurement_sd = share_of_sd * sd;
    try {
      const double ll = log_likelihood(m, on, fo).log_likelihood;
      if (std::isfinite(ll) && ll > best_ll) best_ll = ll, best = m.measurement_sd;
    } catch (const Error&) {
      // this σ cannot be filtered: the others decide
    }
  }
  return best;
}

}  // namespace vehs::likelihood::detail
