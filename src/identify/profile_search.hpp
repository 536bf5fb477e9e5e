#pragma once
// Internal: the search for the nonlinear parameters θ of the dynamic forces on the profile
// contrast — grids (gaps: quantiles of |x|; λ: a log grid; ω: the largest lines of the residual
// spectrum, scanned), refinement by scans and golden section, and joint Newton steps when there
// are several free entries.
#include "profile_problem.hpp"
#include "vehs/identify/report.hpp"

namespace vehs::identify::detail {

/// Finds the free nonlinear parameters of P's components (stored in them) and records how in
/// `info` (search, newton_iterations). `warm`: the components carry the previous round's θ —
/// skip the grids and refine locally.
void search_theta(Problem& P, ProfileFitReport& info, bool warm);

}  // namespace vehs::identify::detail
