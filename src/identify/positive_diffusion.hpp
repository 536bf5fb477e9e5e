#pragma once
// Internal (term_fit.cpp): a variance rate is > 0 where the data go. When the diffusion
// selection's choice is not (weakly determined terms at the edges of the range: quantised
// records at 20 kHz read x⁴ = −0.10 with a22 < 0 beyond 77 counts of data reaching 87), the
// first later step of the path whose diffusion is > 0 there is taken, else the constant
// diffusion; when none is, the selection stands and identify-vehs refuses to write the model
// (vehs/core/diffusion_in_data.hpp).
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/identify/dictionary.hpp"
#include "vehs/identify/regression.hpp"

namespace vehs::identify::detail {

/// The states the data visit, for the sign of a22: x over the data's range, y over ±4 sd of v̂.
struct StateBox {
  double x_lo = 0.0, x_hi = 0.0, y_sd = 0.0;
};

StateBox state_box(const Dataset& data, double v_sd);

/// Whether a22 = Σ q_j ψ_j is > 0 on a grid over the box (201 values of x; 41 of y when ψ
/// depends on y) and at the rest state (0, 0) when the box holds it (a22 = c x² is no noise at rest),
/// and stays >= 0 for large |x| (vehs/core/diffusion_domain.hpp: 2D + c·x, positive over a
/// positioning rig's few mm, is a model no tool simulates).
bool positive_on(const Dictionary& psi, const Eigen::VectorXd& q, const StateBox& box);

/// The selection's choice moved to a diffusion > 0 over the box (above); the rule says so.
void positive_step(SelectionResult& sel, const QuadraticStats& total, const Dictionary& psi,
                   const std::vector<bool>& keep, const StateBox& box);

}  // namespace vehs::identify::detail
