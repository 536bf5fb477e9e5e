#pragma once
// Internal (regression.cpp): the BIC's best support near the backward path's choice. The path
// drops one term at a time by its t-ratio; among nearly collinear terms (x³, x⁵, x⁷ over a
// weakly nonlinear range) it can drop the true one first and never return: a second outside
// tester's clean Duffing records at ω·Δt 0.0022–0.02 were fitted with x⁵, x⁷ in place of x³,
// the true terms' z up to 9, with 4× more data as well. The lowest BIC over every support with
// the kept terms and at most one free term more than the path's choice is taken (single moves
// from the choice can stop short: {x, x⁵, x⁷} → {x, x³} needs a swap and a removal); when that
// is more than 10⁵ supports, the largest size bound that stays within 10⁵.
#include <vector>

#include "vehs/identify/regression.hpp"

namespace vehs::identify {

/// n log(L/n)/φ + p log n (NaN when L or n leave it undefined).
double bic(double n, double loss, std::size_t terms, double variance_factor);

/// The lowest-BIC support above (`start` itself when none is lower; supports whose Gram matrix
/// is ill-conditioned, > 1e12 as require_well_conditioned, are not candidates).
SupportFit bic_best_subset(const QuadraticStats& total, const SupportFit& start, const std::vector<int>& candidates,
                           const std::vector<bool>& keep, double variance_factor);

}  // namespace vehs::identify
