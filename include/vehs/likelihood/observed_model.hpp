#pragma once
// What the likelihood is a likelihood of: the model SDE of docs/model-file.md (drift, diffusion,
// dynamic effects) together with how it was observed — white measurement noise on x and, for
// harmonic forcing of records started at unrelated times, one phase per record.
//
//     dx = y dt
//     dy = b2(t, x, y, u, v, η) dt + sqrt(a22(x, y)) dB          (Itô)
//     dv = (y − λ v) dt                                          (electromechanical_coupling)
//     dη = −η/τ dt + sqrt(intensity)/τ dW                         (colored_noise)
//     observed: x_k = x(t_k) + ε_k,  ε_k ~ N(0, measurement_sd²) independent
// with b2 = Σ c·term(x, y, u) − k_stop·(x − gap)⁺ + k_stop·(−x − gap_neg)⁺
//           + amplitude·cos(ω t + phase_r) − coupling·v + η   (phase_r: the record's phase).
#include <vector>

#include "vehs/core/model.hpp"

namespace vehs::likelihood {

struct ObservedModel {
  Model model;
  double measurement_sd = 0.0;  ///< standard deviation of the white noise on x (0: none)
  /// harmonic_forcing phase of each record of the data (empty: the model's phase, shared by
  /// every record). Amplitude and omega are always shared.
  std::vector<double> record_phases;
};

}  // namespace vehs::likelihood
