#pragma once
// The "lens" through which diagnose-vehs looks at displacement records: finite-difference
// kinematics (the same as identify's estimators) and one-step residuals whitened by the model's
// own diffusion. The lens is applied identically to the measured records and to the model's
// simulated twins, so every estimator subtlety (the Itô/Stein bias of symmetric kinematics,
// interval-averaged velocities, sensor noise, transients) cancels in the comparison.
//
// Kinematics (sampling interval Δt, rows j of a record of n samples):
//  * Forward (data from an explicit scheme at the recorded step, identify's `forward`/`paper`):
//        row j at sample i = j, v = (x[i+1] − x[i])/Δt, â = (x[i+2] − 2x[i+1] + x[i])/Δt²,
//        Var(â | x_i, v) = a22/Δt (c = 1), n − 2 rows.
//  * Central, stride k (a sensor sampling a continuous process, identify's `uli`/`noisy`):
//        row j at sample i = j + k, h = kΔt, v̂ = (x[i+k] − x[i−k])/2h,
//        â = (x[i+k] − 2x[i] + x[i−k])/h², Var(â | past) = (2/3)·a22/h (c = 2/3), n − 2k rows.
// White sensor noise of standard deviation s adds 6s²/h⁴ to the variance of â (h = Δt forward).
//
// Whitened residual: r = (â − b2(x, v̂, u, t)) / sqrt(c·a22(x, v̂)/h + 6s²/h⁴), with b2 the model's
// drift terms plus the forces of the effects that depend on x or t only (impact_stop,
// harmonic_forcing). Hidden-state effects (electromechanical_coupling, colored_noise) cannot be
// evaluated from (x, v̂) and are left in the residual — on both sides of the comparison, since
// the twins are simulated with them. Units: a22 is the variance rate of dY (docs/model-file.md).
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "vehs/core/model.hpp"
#include "vehs/effects/harmonic_forcing.hpp"
#include "vehs/effects/impact_stop.hpp"

namespace vehs::diagnose {

/// Fast evaluation of a term list and of its derivatives at (x, y, u).
class CompiledTerms {
 public:
  CompiledTerms() = default;
  explicit CompiledTerms(const TermList& terms);

  double value(double x, double y, double u) const;
  /// ∂/∂y; sign(y) contributes the box kernel 1{|y| < w}/w for 2δ(y) (half-width w), as the
  /// identify dictionary does.
  double d_dy(double x, double y, double sign_halfwidth) const;
  double d2_dy2(double x, double y) const;
  double d_dx(double x, double y) const;
  bool empty() const { return mono_.empty() && sign_ == 0.0 && yabs_ == 0.0 && u_ == 0.0 && user_.empty(); }
  bool depends_on_y() const;

 private:
  struct Mono {
    int px, py;
    double c;
  };
  std::vector<Mono> mono_;
  int max_px_ = 0, max_py_ = 0;
  double sign_ = 0.0, yabs_ = 0.0, u_ = 0.0;
  TermList user_;  ///< users' expression terms (evaluated through their parsers)
};

/// Forces of the effects that depend on x or t only.
struct ExplicitForces {
  bool has_stop = false;
  effects::ImpactStop<double> stop;
  bool harmonic = false;
  effects::HarmonicForcing<double> forcing;

  explicit ExplicitForces(const Model& m = Model{});
  double value(double x, double t) const {
    double f = 0.0;
    if (has_stop) f += stop.force(x);
    if (harmonic) f += forcing.force(t);
    return f;
  }
};

enum class Kinematics { Forward, Central };

struct Lens {
  Kinematics kinematics = Kinematics::Central;
  int stride = 1;                ///< k (central only; forward uses 1)
  double dt = 0.0;               ///< sampling interval
  double sensor_noise_sd = 0.0;  ///< s, white noise on x assumed by the whitening

  double h() const { return kinematics == Kinematics::Central ? stride * dt : dt; }
  /// c of Var(â) = c·a22/h.
  double c() const { return kinematics == Kinematics::Central ? 2.0 / 3.0 : 1.0; }
  double noise_variance() const {
    const double hh = h();
    return 6.0 * sensor_noise_sd * sensor_noise_sd / (hh * hh * hh * hh);
  }
  /// Samples lost before the first row and after the last one.
  std::size_t lead() const { return kinematics == Kinematics::Central ? static_cast<std::size_t>(stride) : 0; }
  std::size_t trail() const { return kinematics == Kinematics::Central ? static_cast<std::size_t>(stride) : 2; }
  std::size_t rows(std::size_t n) const { return n > lead() + trail() ? n - lead() - trail() : 0; }
  /// Kinematics of the row centred at sample i (lead() <= i < n − trail()).
  void at(const double* x, std::size_t i, double& xi, double& v, double& a) const {
    if (kinematics == Kinematics::Central) {
      const std::size_t k = static_cast<std::size_t>(stride);
      const double hh = h();
      xi = x[i];
      v = (x[i + k] - x[i - k]) / (2.0 * hh);
      a = ((x[i + k] - x[i]) - (x[i] - x[i - k])) / (hh * hh);
    } else {
      xi = x[i];
      v = (x[i + 1] - x[i]) / dt;
      a = ((x[i + 2] - x[i + 1]) - (x[i + 1] - x[i])) / (dt * dt);
    }
  }
  std::string describe() const;
  /// Empty when valid, else a one-line reason.
  std::string invalid_reason() const;
};

/// A model seen through a lens: whitened one-step residuals.
class ModelLens {
 public:
  ModelLens(const Model& model, const Lens& lens);
  const Lens& lens() const { return lens_; }
  double b2(double x, double v, double u, double t) const {
    return drift_.value(x, v, u) + forces_.value(x, t);
  }
  double a22(double x, double v) const { return diffusion_.value(x, v, 0.0); }
  /// Variance of â given the state under the model (c·a22/h + 6s²/h⁴); <= 0 when a22 is.
  double residual_variance(double x, double v) const {
    return lens_.c() * a22(x, v) / lens_.h() + noise_var_;
  }
  /// Whitened residual; `ok` false when the model's residual variance is not positive there.
  double residual(double x, double v, double a, double u, double t, bool& ok) const {
    const double var = residual_variance(x, v);
    ok = var > 0.0 && std::isfinite(var);
    return ok ? (a - b2(x, v, u, t)) / std::sqrt(var) : 0.0;
  }
  bool has_hidden_effects() const { return hidden_; }

 private:
  Lens lens_;
  CompiledTerms drift_, diffusion_;
  ExplicitForces forces_;
  double noise_var_ = 0.0;
  bool hidden_ = false;
};

}  // namespace vehs::diagnose
