#pragma once
// Internal: long-run variance factors 1 + 2 Σ_{l=1..L} ρ_l of the drift and diffusion residuals
// (the φ of identify's BIC: residuals of finite differences are correlated over a few lags).
#include <vector>

#include <Eigen/Dense>

#include "diffusion_pass.hpp"

namespace vehs::identify::detail {

/// Long-run variance factors 1 + 2 Σ_{l=1..L} ρ_l of drift residuals r and of diffusion
/// residuals e = z − ψ·q over a span (prefix sums over clipped windows).
struct LongRun {
  double r2 = 0, r_lr = 0, e2 = 0, e_lr = 0;
  void add(const LongRun& o) {
    r2 += o.r2;
    r_lr += o.r_lr;
    e2 += o.e2;
    e_lr += o.e_lr;
  }
};

/// Adds the long-run sums of one span: drift residuals over windows of lr_r rows, diffusion
/// residuals z − ψ·q over windows of lr_e rows.
void long_run_span(const Context& cx, const DiffusionSetup& ds, const Eigen::VectorXd& q, int lr_r, int lr_e,
                   const Span& sp, LongRun& acc);

}  // namespace vehs::identify::detail
