#pragma once
// The physical parameter names of the paper (β, k_i, 2D, 2Q) over the term coefficients of a
// model, so tables, sweeps and studies speak the user's language — the one parser of parameter
// names (vehs-compare's tables, fpk sweeps, consistency studies):
//   beta = −drift["y"], k<i> = −drift["x^i"] (i < 100), 2D = diffusion["1"], 2Q = diffusion["x^2"],
//   D and Q their halves; a term-like effect's parameter by its name (coulomb_friction.mu =
//   −drift["sign(y)"], quadratic_damping.c, nonlinear_damping.c_x2y / c_y3,
//   velocity_dependent_noise.q_y2 = diffusion["y^2"]); any other term as drift[<term>] or
//   diffusion[<term>] (the coefficient itself), and dynamic effects' parameters as
//   <effect>.<param>. An effect's parameter may be named alone ("mu") where one effect of the
//   catalogue has it.
#include <optional>
#include <string>
#include <vector>

#include "vehs/core/model.hpp"

namespace vehs {

struct PhysicalParameter {
  std::string name;                 ///< "beta", "k3", "2D", "coulomb_friction.mu", "impact_stop.gap"
  /// The coefficient it is read from, "drift[sign(y)]" (empty for a dynamic effect's parameter):
  /// value = sign · coefficient.
  std::string coefficient;
  double sign = 1.0;
  double value = 0.0;
  std::optional<double> stderr_;    ///< when the model file reports one
};

/// All parameters of a model in a stable order: beta, k0, k1, …, other drift terms, 2D, 2Q,
/// other diffusion terms, effect parameters.
std::vector<PhysicalParameter> physical_parameters(const Model& m);

/// Reads a parameter by physical name (0 when the term is absent); throws vehs::Error for a name
/// that is not of the forms above.
double get_parameter(const Model& m, const std::string& name);
/// Sets a parameter by physical name (finite), adding the term when absent (coulomb_friction.mu
/// adds sign(y)); a dynamic effect's parameter must belong to an effect of the model.
void set_parameter(Model& m, const std::string& name, double value);

/// Powers of the data's length, time and input units in a parameter (named as above): beta
/// time^-1, k3 length^-2 time^-2, coulomb_friction.mu length time^-2, 2D length^2 time^-3.
struct Dimension {
  int length = 0;
  int time = 0;
  int input = 0;
};
Dimension parameter_dimension(const std::string& name);

}  // namespace vehs
