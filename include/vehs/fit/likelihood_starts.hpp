#pragma once
// Several starts of identify's likelihood: the optimiser is local, and the moment fit auto chooses
// need not lie in the basin of the global maximum (Silverbox: from the forward fit the likelihood
// stops 10 588 nats below the optimum reached from the uli fit, with a spurious x^2*y). Every moment
// fit the data admit (uli, noisy, forward; a fit with sensor noise also with the likelihood's own
// scan of the noise start) is fitted briefly — few whitening rounds on a share of the data, no
// selection, no bias correction, Fisher information — and the full refinement runs only from the
// highest log L.
#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"
#include "vehs/likelihood/refine.hpp"

namespace vehs {

/// A moment fit to start from: the estimator's name and its model, or why it failed.
struct MomentCandidate {
  std::string estimator;
  std::optional<Model> model;
  std::string failure;
};

/// The other moment fits of the data, computed only when the likelihood runs.
using MomentCandidates = std::function<std::vector<MomentCandidate>()>;

/// Whitening rounds of a start's brief fit.
inline constexpr int kBriefRounds = 2;
/// Larger data are fitted briefly on a share of about this many samples (eight evenly spaced
/// pieces of every record, likelihood/detail/data_share.hpp): the basins differ by thousands of
/// nats on the whole data (Silverbox: 12 600 between the forward and the uli start), by hundreds on
/// an eighth of them, at an eighth of the cost.
inline constexpr std::size_t kBriefSamples = 8000;

struct LikelihoodStart {
  std::string name;                  ///< "auto: forward", "uli", "noisy (measurement_sd scanned)"
  std::size_t candidate = 0;         ///< index of its moment fit (0: the given one)
  double measurement_sd = 0.0;       ///< the sensor noise it starts at (0: the likelihood's scan)
  double log_likelihood = std::numeric_limits<double>::quiet_NaN();  ///< after the brief fit (on its share)
  double seconds = 0.0;              ///< of the brief fit
  std::string status;                ///< "chosen", "fitted", "same as …", "failed: …"
};

/// The starts of `candidates` (candidates[0] the given fit): one per distinct moment fit, two
/// (its noise and the scan) for a fit with sensor noise when the likelihood estimates it;
/// failed and repeated fits are listed with their status and not fitted.
std::vector<LikelihoodStart> likelihood_starts(const std::vector<MomentCandidate>& candidates,
                                               bool estimate_measurement_noise);

/// The options of a brief fit: at most kBriefRounds rounds, no selection, no bias correction,
/// Fisher information, no log.
likelihood::RefineOptions brief_options(const likelihood::RefineOptions& options);

/// The data of a brief fit: all of `data` up to kBriefSamples, else a share of about that many
/// (eight evenly spaced pieces of every record).
Dataset brief_share(const Dataset& data);

/// Fits every start briefly (see above) and marks the highest log L "chosen"; returns its
/// refined model, or nothing when every brief fit failed. Logs one line per start; calls `fitted`
/// (when given) after each brief fit.
std::optional<likelihood::ObservedModel> best_start(std::vector<LikelihoodStart>& starts,
                                                    const std::vector<MomentCandidate>& candidates,
                                                    const Dataset& data, const likelihood::RefineOptions& options,
                                                    const std::function<void()>& fitted = {});

}  // namespace vehs
