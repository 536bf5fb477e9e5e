#pragma once
// The shape of an observed model as the filter kernels see it: which terms, which effects, how
// large the Gaussian moment tables must be; and its coefficients in a scalar type T (double, or
// ceres::Jet carrying derivatives with respect to the fitted parameters).
#include <string>
#include <vector>

#include "vehs/core/model.hpp"
#include "vehs/effects/harmonic_forcing.hpp"
#include "vehs/effects/impact_stop.hpp"

namespace vehs::likelihood::detail {

struct Structure {
  std::vector<Term> drift;      ///< b2 terms, in the order of Coefficients::drift
  std::vector<Term> diffusion;  ///< a22 terms, in the order of Coefficients::diffusion
  int max_px = 1, max_py = 1;   ///< moment table: powers of x and y needed (with derivatives)
  /// Highest power of x needed in the moment table at each power of y (−1: none): the table
  /// is filled only where a term, a derivative or the recursion reads it.
  int a_max_by_b[6] = {1, -1, -1, -1, -1, -1};
  bool needs_sd = false;        ///< a term or effect needs the standard deviations (sign, |y|, stops)
  bool impact = false, harmonic = false, electro = false, colored = false;
  bool drive = false;           ///< a `u` term is present
  /// A drift term sign(y) (Coulomb friction): its expected slope μ·2φ(0)/√P_yy grows without
  /// bound as the velocity becomes known, so the filter checks each interval's covariance and
  /// has a backward-Euler fallback (block_filter.hpp); other models keep the plain RK4 retries.
  bool friction = false;
  int dim() const { return electro || colored ? 4 : 2; }

  /// The structure of a model's terms and dynamic effects; throws vehs::Error (prefixed with
  /// `where`) for terms the filter cannot take (powers beyond the moment tables, sign(y) or u
  /// in a22).
  static Structure of(const Model& m, const std::string& where);
};

template <class T>
struct Coefficients {
  std::vector<T> drift, diffusion;
  effects::ImpactStop<T> stop;
  effects::HarmonicForcing<T> forcing;
  T lambda{}, coupling{};
  T tau{}, intensity{};
  T measurement_var{};  ///< measurement_sd²
};

}  // namespace vehs::likelihood::detail
