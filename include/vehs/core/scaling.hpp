#pragma once
// Units of a fit: data in metres, millimetres or non-dimensional must give the same model up to
// the unit conversion. Estimators compare numbers against absolute floors and tolerances
// (conditioning, pivots, variance floors), so they work on data scaled to O(1) and the model is
// transformed back. One convention, used by identify and by the likelihood fits:
//
//   physical = scale · internal:   x = L·x̃,  t = T·t̃,  u = U·ũ,  hence y = (L/T)·ỹ.
//
// The drift b2 is an acceleration (L/T²) and the diffusion a22 a variance rate of y (L²/T³), so a
// term x^px·y^py with internal coefficient c̃ has the physical coefficient
//   drift:      c = c̃ · (L/T²) / (L^px · (L/T)^py)
//   diffusion:  c = c̃ · (L²/T³) / (L^px · (L/T)^py)
// (sign(y) is dimensionless, y·|y| is (L/T)², u is U). Effect parameters carry their own units
// (impact_stop.gap: L, harmonic_forcing.omega: 1/T, colored_noise.intensity: L²/T³, …; see
// effect_parameter_scale). Standard errors and covariances transform with the same factors.
//
// natural_scales chooses powers of ten near the data's own magnitudes, so data already of O(1)
// (the paper's non-dimensional records) are not touched at all, and the same record in m and in
// mm maps to the same internal numbers (up to the rounding of one multiplication).
#include <string>
#include <string_view>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"

namespace vehs {

/// Physical size of one internal unit of length, time and input (drive u).
struct Scales {
  double length = 1.0;
  double time = 1.0;
  double input = 1.0;

  bool is_identity() const { return length == 1.0 && time == 1.0 && input == 1.0; }
  /// Empty when valid (finite and > 0), else a one-line reason.
  std::string invalid_reason() const;
};

/// Powers of ten nearest (in log) to the RMS of x about its record means (length), to
/// RMS(x)/RMS(Δx/Δt) (time: 1/ω of the motion) and to the RMS of u (input). A scale whose
/// figure is 0 or not finite (constant x, no drive) is 1.
Scales natural_scales(const Dataset& data);

/// Physical value of one internal unit of a drift / diffusion coefficient of `term`.
double drift_coefficient_scale(const Term& term, const Scales& s);
double diffusion_coefficient_scale(const Term& term, const Scales& s);
/// Physical value of one internal unit of an effect parameter (1 for dimensionless ones).
double effect_parameter_scale(EffectId effect, std::string_view parameter, const Scales& s);

/// The dataset in internal units: x/L, u/U, record t0 and dt divided by T (y, when present, by
/// L/T). Sources, ids and lines are kept.
Dataset to_internal(const Dataset& data, const Scales& s);

/// A model (coefficients, standard errors, effect parameters and their errors, the covariance,
/// the fit's sampling interval and sensor noise) converted from internal to physical units, or
/// back with to_internal.
Model to_physical(const Model& internal, const Scales& s);
Model to_internal(const Model& physical, const Scales& s);

/// Terms (a library) in internal units: a user's expression term becomes its function of the
/// internal state (vehs/core/user_function.hpp); the others are unchanged.
std::vector<Term> to_internal(std::vector<Term> terms, const Scales& s);

/// An effect's parameters and standard errors, converted (factor^power, power ±1).
Effect scale_effect(const Effect& effect, const Scales& s, int power);

}  // namespace vehs
