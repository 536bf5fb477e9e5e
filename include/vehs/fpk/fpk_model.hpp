#pragma once
// A model as the stationary Fokker–Planck equation sees it (stationary.hpp describes the equation).
#include <string>

#include "vehs/core/model.hpp"
#include "vehs/effects/impact_stop.hpp"

namespace vehs::fpk {

/// The drift and diffusion as the FPK sees them: model terms plus the impact_stop force.
/// The constructor checks that a stationary 2-D FPK exists for the model (no `u` term, no
/// dynamic effect other than impact_stop, finite coefficients, a confining potential,
/// dissipation in y) and throws vehs::Error naming `where` and the reason otherwise.
class FpkModel {
 public:
  explicit FpkModel(const Model& model, const std::string& where = "model");

  double b2(double x, double y) const;        ///< full drift of dY
  double db2_dy(double x, double y) const;    ///< ∂b2/∂y (0 a.e. for sign(y))
  double a22(double x, double y) const;       ///< variance rate of dY
  double da22_dy(double x, double y) const;
  double d2a22_dy2(double x, double y) const;
  /// U'(x) = −b2(x, 0): the restoring force of the x-only part of the drift (incl. stops).
  double restoring_force(double x) const;
  /// U(x) = ∫₀ˣ U'(s) ds (exact for polynomials and stops).
  double potential(double x) const;
  /// Effective damping at displacement x for velocities of size v: −(b2(x,v) − b2(x,−v))/(2v).
  double damping(double x, double v) const;
  /// Local effective temperature a22(x, 0) / (2·β_eff), with β_eff the damping at the
  /// self-consistent velocity scale v = sqrt(T) (exact for linear damping).
  double temperature(double x) const;
  bool has_sign_y() const { return has_sign_y_; }
  const Model& model() const { return model_; }
  const std::string& where() const { return where_; }

 private:
  Model model_;
  std::string where_;
  effects::ImpactStop<double> stop_;
  bool has_stop_ = false, has_sign_y_ = false;
};

}  // namespace vehs::fpk
