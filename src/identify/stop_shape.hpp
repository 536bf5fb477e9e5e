#pragma once
// Internal: the force shape of impact stops along a record, as the kinematics see it.
#include <cstddef>

namespace vehs::identify::detail {

/// Stop force shape −(x − gp)⁺ + (−x − gn)⁺ at every sample of a record; with tent_k > 0 its
/// average over the kernel of the central second difference at stride tent_k (weights
/// (k − |s|)/k² over s ∈ [−k, k] samples, x linear between samples), which is what the ULI
/// acceleration measures of a force that is not smooth in time.
void stop_shape(const double* x, std::size_t n, double gp, double gn, int tent_k, double* out);

}  // namespace vehs::identify::detail
