#pragma once
// Internal: identify's pilot fits on a subsample (the first rows of every record): the
// uncorrected full-library drift, the lag autocorrelations of its residuals (how the data were
// sampled: sampling_rule), an OLS diffusion (weights of the final fit), the Itô-corrected drift
// (the O(h²) correction) and the long-run variance factors of the BIC.
#include <cstddef>
#include <vector>

#include <Eigen/Dense>

#include "diffusion_pass.hpp"
#include "drift_pass.hpp"

namespace vehs::identify::detail {

/// Pilot fits on a subsample (the first rows of every record).
struct Pilot {
  int k = 1;
  bool central = true;
  Target target = Target::Uli;
  double V = 0, rho_1 = 0, rho_k = 0, rho_2k = 0, rho_3k = 0, C2k = 0, C3k = 0;
  double noise_share = 0, rows = 0;
  double v_sd = 0;
  Eigen::VectorXd q;          // diffusion coefficients (full ψ library, OLS)
  Eigen::VectorXd c;          // Itô-corrected full-library drift (after finish_pilot)
  double mean_z = 0;   // mean diffusion target
  double drift_lr = 1, diffusion_lr = 1;  // long-run variance factors (after finish_pilot)
  // kept for finish_pilot
  std::vector<Span> spans;
  DriftStats drift;
  DiffusionSetup ds;
  // a state-dependent diffusion: the drift under which rows too stiff for the lens are left out
  // (the drift refitted on the rows the first fit's mask kept), when they were
  bool masked = false;
  DriftModel lens;
};

/// Whether the diffusion library has a term other than the constant (the sampling rule and the
/// sensor-noise covariance then read residuals standardized by the fitted diffusion).
bool state_dependent(const Dictionary& psi);

/// The weights of a diffusion fit from the pilot's OLS diffusion: 1/max(a22, 5 % of the mean target).
DiffusionWeights diffusion_weights(const Pilot& p);

/// The uncorrected full-library drift fit, residual autocorrelations and OLS diffusion fit at
/// `kin` on at most ~pilot_rows rows; with a state-dependent diffusion and central kinematics
/// the drift and diffusion fits leave out the rows where the lens does not hold (lens_mask.hpp).
Pilot run_pilot(const Dataset& d, const Dictionary& phi, const Dictionary& psi, const Kinematics& kin,
                Target target, std::size_t pilot_rows, const double* known);

/// Completes a pilot in the final kinematics: the Itô-corrected drift and the long-run variance
/// factors of the drift and diffusion residuals.
void finish_pilot(Pilot& p, const Dataset& d, const Dictionary& phi, const Dictionary& psi, const Kinematics& kin,
                  const double* known);

}  // namespace vehs::identify::detail
