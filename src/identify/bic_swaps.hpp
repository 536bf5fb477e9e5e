#pragma once
// Internal (regression.cpp): the BIC's best support near the backward path's choice. The path
// drops one term at a time by its t-ratio; among nearly collinear terms (x³, x⁵, x⁷ over a
// weakly nonlinear range) it can drop the true one first and never return: a second outside
// tester's clean Duffing records at ω·Δt 0.0022–0.02 were fitted with x⁵, x⁷ in place of x³,
// the true terms' z up to 9, with 4× more data as well. The BIC's best support among all with at
// most one term more than the path's choice is taken (every subset when there are ≤ 10⁵ of them:
// single moves from the choice can stop short, {x, x⁵, x⁷} → {x, x³} needs a swap and a removal);
// beyond that, single moves — add a term, remove one, swap one for another — while the BIC falls.
#include <vector>

#include "vehs/identify/regression.hpp"

namespace vehs::identify {

/// The BIC n log(L/n)/φ + p log n of a fit (NaN for a failed or ill-conditioned one).
double support_bic(const QuadraticStats& total, const SupportFit& fit, double variance_factor);

/// The lowest-BIC support that holds the kept terms and at most one term more than `start`
/// (every such subset of `candidates` when there are at most 10⁵, else bic_local_search).
SupportFit bic_best_subset(const QuadraticStats& total, const SupportFit& start, const std::vector<int>& candidates,
                           const std::vector<bool>& keep, double variance_factor);

/// The support reached from `start` by single moves within `candidates` (terms in `keep` stay)
/// while the BIC falls; `start` itself when no move lowers it.
SupportFit bic_local_search(const QuadraticStats& total, const SupportFit& start, const std::vector<int>& candidates,
                            const std::vector<bool>& keep, double variance_factor);

}  // namespace vehs::identify
