#pragma once
// The rule every tool applies to a model's diffusion before it simulates, diagnoses or solves the
// Fokker-Planck equation: a22 is a variance rate, so a22(x, 0) (the rate at rest, the part no
// velocity term can offset) must stay >= 0 as |x| grows without bound. It does when the highest
// power of x among the y-free diffusion terms is even with a positive coefficient; 2D - c x^2
// (negative beyond |x| = sqrt(2D / c)) or any odd leading power does not. The rule is global (it
// does not depend on a grid, the initial states or the data), so simulate-vehs, diagnose-vehs and
// fpk-stationary refuse the same models.
#include <string>

#include "vehs/core/model.hpp"

namespace vehs {

/// Why `model`'s a22(x, 0) turns negative for large |x| ("" when it does not), e.g.
/// "diffusion a22(x, 0) = 0.02 - 0.01·x^2 has leading term -0.01·x^2 and is negative for |x| > 1.414
/// (a22 is a variance rate and must be >= 0)".
std::string diffusion_negative_at_large_x(const Model& model);

}  // namespace vehs
