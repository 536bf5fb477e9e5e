#pragma once
// The physical parameter names of the paper (β, k_i, 2D, 2Q) over the term coefficients of a
// model, so tables, sweeps and studies speak the user's language — the one parser of parameter
// names (vehs-compare's tables, fpk sweeps, consistency studies):
//   beta = −drift["y"], k<i> = −drift["x^i"] (i < 100), 2D = diffusion["1"], 2Q = diffusion["x^2"],
//   D and Q their halves; any other term as drift[<term>] or diffusion[<term>] (the coefficient
//   itself), and effect parameters as <effect>.<param>.
#include <optional>
#include <string>
#include <vector>

#include "vehs/core/model.hpp"

namespace vehs {

struct PhysicalParameter {
  std::string name;                 ///< "beta", "k3", "2D", "drift[x^2*y]", "impact_stop.gap"
  double value = 0.0;
  std::optional<double> stderr_;    ///< when the model file reports one
};

/// All parameters of a model in a stable order: beta, k0, k1, …, other drift terms, 2D, 2Q,
/// other diffusion terms, effect parameters.
std::vector<PhysicalParameter> physical_parameters(const Model& m);

/// Reads a parameter by physical name (0 when the term is absent); throws vehs::Error for a name
/// that is not of the forms above.
double get_parameter(const Model& m, const std::string& name);
/// Sets a parameter by physical name (finite), adding the term when absent; an effect parameter
/// must belong to an effect of the model.
void set_parameter(Model& m, const std::string& name, double value);

}  // namespace vehs
