#pragma once
// Steppers for the model SDE (system.hpp), all behind one concept (boost.odeint style):
//
//   struct Stepper {
//     static constexpr Scheme scheme;
//     static constexpr int normals_per_source;  // standard normals used per noise source per step
//     template <class System, class Xi>
//     void step(const System& sys, typename System::State& s, double t, double h, const Xi& xi) const;
//   };
//
// `s` holds System::lanes independent records advanced in lockstep from time t to t + h;
// `xi` is an Eigen array (lanes × normals_per_source·System::noises) of independent N(0, 1)
// values, column normals_per_source·k + i being normal i of noise source k. A stepper never draws
// random numbers itself, so the caller decides how increments are generated (the simulator:
// counter-based Philox; the convergence tests: exact aggregation of fine increments).
//
// Orders for this model (noise on y only, amplitude σ(x) — Itô and Stratonovich coincide and the
// Milstein correction vanishes; measured in tests/sim/test_convergence.cpp):
//   EulerMaruyama  strong 1.0, weak 1.0 (strong 0.5 when σ depends on y)
//   Rk4Euler       the paper's Eq. 30: RK4 on the drift, then Euler noise σ(Xₙ)·√h·ξ.
//                  Strong 1.0, weak 1.0; tiny deterministic error.
//   Baoab          Leimkuhler–Matthews splitting B A O A B: B = half kick by b2 + β·y (everything
//                  but the linear damping), A = half drift of x, O = exact Ornstein–Uhlenbeck
//                  step of dy = −β·y dt + σ dW with σ frozen at the current (x, y).
//                  Strong 1.0; weak 2.0 for smooth b2 and σ = σ(x) (reduces exactly to
//                  Leimkuhler–Matthews BAOAB when σ is constant). Hidden states: v is advanced by
//                  its exact flow for y frozen over h/2 on either side of O, η by its exact OU step.
//   Taylor15       Kloeden–Platen strong order-1.5 Itô–Taylor scheme (KP 10.4) written out for
//                  this noise structure:
//                    ΔW = √h ξ₁,  ΔZ = ∫₀ʰ (W_s − W_0) ds = ½ h^{3/2} (ξ₁ + ξ₂/√3)
//                    L⁰f = ∂_t f + y ∂_x f + b2 ∂_y f + ½σ² ∂²_y f (+ hidden drifts · ∂_z f)
//                    X₊ = X + y h + σ ΔZ + ½ b2 h²
//                    Y₊ = Y + b2 h + σ ΔW + σ ∂_y b2 ΔZ + L⁰σ (ΔW h − ΔZ) + ½ L⁰b2 h²
//                         + ½ σσ_y (ΔW² − h) + ½ σ(σ_y² + σσ_yy)(⅓ΔW² − h)ΔW   [σ depends on y]
//                         + s_η ΔZ_η                                          [coloured noise]
//                    v₊ = v + (y − λv) h + σ ΔZ + ½ (b2 − λ(y − λv)) h²
//                    η₊ = η − η/τ h + s_η ΔW_η − (s_η/τ) ΔZ_η + ½ η/τ² h²
//                  All mixed multiple integrals I_(j1,j2) with j1 ≠ j2 have zero coefficients
//                  here (σ does not depend on η; the η noise is additive). Strong 1.5 for smooth
//                  coefficients; non-smooth terms (sign(y), impact stops) reduce the order.
//                  Where σ = 0 its derivatives are taken as 0.
#include <cmath>

#include <Eigen/Core>

#include "vehs/sim/simulate.hpp"
#include "vehs/sim/system.hpp"

namespace vehs::sim {

struct EulerMaruyamaStepper {
  static constexpr Scheme scheme = Scheme::EulerMaruyama;
  static constexpr int normals_per_source = 1;

  template <class System, class Xi>
  VEHS_SIM_INLINE void step(const System& sys, typename System::State& s, double t, double h,
                            const Xi& xi) const {
    typename System::State f;
    typename System::Noise g;
    sys.drift(t, s, f);
    sys.noise(s, g);
    const double sqh = std::sqrt(h);
    s += h * f;
    for (int k = 0; k < System::noises; ++k)
      s.col(System::noise_component(k)) += sqh * g.col(k) * xi.col(k);
  }
};

struct Rk4EulerStepper {
  static constexpr Scheme scheme = Scheme::Rk4Euler;
  static constexpr int normals_per_source = 1;

  template <class System, class Xi>
  VEHS_SIM_INLINE void step(const System& sys, typename System::State& s, double t, double h,
                            const Xi& xi) const {
    using State = typename System::State;
    typename System::Noise g;
    sys.noise(s, g);
    // k1 + 2 k2 + 2 k3 + k4 accumulated as the stages are computed: only two stage arrays are
    // alive at a time (measured 15 % faster than keeping all four: fewer register spills)
    State k, sum;
    sys.drift(t, s, k);
    sum = k;
    sys.drift(t + 0.5 * h, State(s + (0.5 * h) * k), k);
    sum += 2.0 * k;
    sys.drift(t + 0.5 * h, State(s + (0.5 * h) * k), k);
    sum += 2.0 * k;
    sys.drift(t + h, State(s + h * k), k);
    sum += k;
    s += (h / 6.0) * sum;
    const double sqh = std::sqrt(h);
    for (int src = 0; src < System::noises; ++src)
      s.col(System::noise_component(src)) += sqh * g.col(src) * xi.col(src);
  }
};

struct BaoabStepper {
  static constexpr Scheme scheme = Scheme::Baoab;
  static constexpr int normals_per_source = 1;

  template <class System, class Xi>
  VEHS_SIM_INLINE void step(const System& sys, typename System::State& s, double t, double h,
                            const Xi& xi) const {
    const double beta = sys.linear_damping();
    // O step coefficients: y ← e^{−βh} y + sqrt((1 − e^{−2βh}) / 2β) σ ξ  (→ √h σ ξ as β → 0)
    const double decay = std::exp(-beta * h);
    const double spread = beta != 0.0 ? std::sqrt(-std::expm1(-2.0 * beta * h) / (2.0 * beta))
                                      : std::sqrt(h);
    s.col(1) += (0.5 * h) * sys.force_nl(t, s);  // B
    s.col(0) += (0.5 * h) * s.col(1);            // A
    sys.hidden_half_flow(s, 0.5 * h);
    const typename System::Lanes sigma = sys.sigma(s);
    s.col(1) = decay * s.col(1) + spread * sigma * xi.col(0);  // O
    if constexpr (System::has_colored) sys.colored_exact(s, h, xi.col(1));
    sys.hidden_half_flow(s, 0.5 * h);
    s.col(0) += (0.5 * h) * s.col(1);                // A
    s.col(1) += (0.5 * h) * sys.force_nl(t + h, s);  // B
  }
};

struct Taylor15Stepper {
  static constexpr Scheme scheme = Scheme::Taylor15;
  static constexpr int normals_per_source = 2;

  template <class System, class Xi>
  VEHS_SIM_INLINE void step(const System& sys, typename System::State& s, double t, double h,
                            const Xi& xi) const {
    using Lanes = typename System::Lanes;
    const auto& m = sys.model();
    const auto j = sys.jet(t, s);
    const double sqh = std::sqrt(h), h2 = h * h;
    const Lanes dW = sqh * xi.col(0);
    const Lanes dZ = (0.5 * h * sqh) * (xi.col(0) + xi.col(1) * (1.0 / std::sqrt(3.0)));
    const Lanes y = s.col(1);
    const Lanes sig2 = j.sigma * j.sigma;
    Lanes L0b2 = j.b2_t + y * j.b2_x + j.b2 * j.b2_y + 0.5 * sig2 * j.b2_yy;
    const Lanes L0sigma = y * j.sigma_x + j.b2 * j.sigma_y + 0.5 * sig2 * j.sigma_yy;
    Lanes gv, geta;
    if constexpr (System::has_electro) {
      gv = y - m.lambda * s.col(System::electro_index);
      L0b2 -= m.coupling * gv;
    }
    if constexpr (System::has_colored) {
      geta = -s.col(System::colored_index) / m.tau;
      L0b2 += geta;
    }
    Lanes dy = j.b2 * h + j.sigma * dW + j.sigma * j.b2_y * dZ + L0sigma * (dW * h - dZ) + (0.5 * h2) * L0b2;
    if (m.noise_depends_on_y) {
      const Lanes dW2 = dW * dW;
      dy += 0.5 * j.sigma * j.sigma_y * (dW2 - h) +
            0.5 * j.sigma * (j.sigma_y * j.sigma_y + j.sigma * j.sigma_yy) * (dW2 * (1.0 / 3.0) - h) * dW;
    }
    if constexpr (System::has_electro) {
      s.col(System::electro_index) += gv * h + j.sigma * dZ + (0.5 * h2) * (j.b2 - m.lambda * gv);
    }
    if constexpr (System::has_colored) {
      const double s_eta = std::sqrt(m.intensity) / m.tau;
      const Lanes dW_eta = sqh * xi.col(2);
      const Lanes dZ_eta = (0.5 * h * sqh) * (xi.col(2) + xi.col(3) * (1.0 / std::sqrt(3.0)));
      dy += s_eta * dZ_eta;
      s.col(System::colored_index) += geta * h + s_eta * dW_eta - (s_eta / m.tau) * dZ_eta -
                                      (0.5 * h2 / m.tau) * geta;
    }
    s.col(0) += y * h + j.sigma * dZ + (0.5 * h2) * j.b2;
    s.col(1) += dy;
  }
};

}  // namespace vehs::sim
