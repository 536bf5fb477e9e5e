#pragma once
// Internal: how identify turns a record into regression rows (finite differences), and what the
// diffusion fit regresses for each estimator.
#include <cstddef>

#include "vehs/core/fit_info.hpp"
#include "vehs/identify/dictionary.hpp"

namespace vehs::identify::detail {

/// Which finite differences turn a record into regression rows. Row j of a record of n samples
/// sits at sample i = j (forward) or i = j + k (central, stride k, h = kΔt).
struct Kinematics {
  bool central = true;
  int k = 1;
  double dt = 1.0;
  double h = 1.0;  // k·dt (central) or dt (forward)

  Kinematics(bool central_, int k_, double dt_)
      : central(central_), k(central_ ? k_ : 1), dt(dt_), h(central_ ? k_ * dt_ : dt_) {}

  std::size_t rows(std::size_t n) const {
    const std::size_t lost = central ? 2 * static_cast<std::size_t>(k) : 2;
    return n > lost ? n - lost : 0;
  }
  std::size_t sample(std::size_t j) const { return central ? j + static_cast<std::size_t>(k) : j; }

  /// Rows [j0, j0 + m) of a record into a block.
  void load(const double* x, const double* u, std::size_t j0, int m, RowBlock& b) const {
    b.m = m;
    if (central) {
      const auto ks = static_cast<std::size_t>(k);
      const double* xm = x + j0;
      const double* x0 = x + j0 + ks;
      const double* xp = x + j0 + 2 * ks;
      const double inv2h = 1.0 / (2.0 * h), invh2 = 1.0 / (h * h);
      for (int c = 0; c < m; ++c) {
        b.x[c] = x0[c];
        b.v[c] = (xp[c] - xm[c]) * inv2h;
        b.a[c] = ((xp[c] - x0[c]) - (x0[c] - xm[c])) * invh2;
      }
      if (u)
        for (int c = 0; c < m; ++c) b.u[c] = u[j0 + ks + static_cast<std::size_t>(c)];
    } else {
      const double* x0 = x + j0;
      const double* x1 = x + j0 + 1;
      const double* x2 = x + j0 + 2;
      const double invdt = 1.0 / dt, invdt2 = 1.0 / (dt * dt);
      for (int c = 0; c < m; ++c) {
        b.x[c] = x0[c];
        b.v[c] = (x1[c] - x0[c]) * invdt;
        b.a[c] = ((x2[c] - x1[c]) - (x1[c] - x0[c])) * invdt2;
      }
      if (u)
        for (int c = 0; c < m; ++c) b.u[c] = u[j0 + static_cast<std::size_t>(c)];
    }
    if (!u)
      for (int c = 0; c < m; ++c) b.u[c] = 0.0;
  }
};

/// The diffusion target of an estimator (diffusion_target in diffusion_pass.hpp).
enum class Target { RawKM, Forward, Uli, Noisy };

inline Target target_of(Estimator e) {
  switch (e) {
    case Estimator::Paper: return Target::RawKM;
    case Estimator::Forward: return Target::Forward;
    case Estimator::Noisy: return Target::Noisy;
    default: return Target::Uli;
  }
}

}  // namespace vehs::identify::detail
