#pragma once
// Generic steppers for stochastic (and ordinary) differential equations, in the style of
// boost.odeint: a stepper knows a scheme, a system knows its equations, and neither knows the
// other's types. The simulator (vehs/sim/simulate.hpp) runs the harvester model through them;
// a user's own system in C++ runs through them the same way (tests/sim/test_steppers.cpp).
//
// States. Any Eigen array (or vector) with `s + a * f` arithmetic, over any scalar type (double,
// or e.g. ceres::Jet for the deterministic Rk4 of a likelihood). A state with one column is one
// trajectory (entry c is component c, System::Lanes a scalar); a state with several columns holds
// independent trajectories in its rows ("lanes", advanced in lockstep for SIMD; System::Lanes an
// Eigen column) and component c in column c. `component<System>(s, c)` gives either. Time and step
// are doubles (or any type the system accepts).
//
// Random numbers. A stepper never draws them: `xi` holds independent N(0, 1) values with one
// column (or entry) per normal, normal i of noise source k at normals_per_source·k + i, so the
// caller decides how increments are generated (the simulator: counter-based Philox; the
// convergence tests: exact aggregation of fine increments).
//
// The system concepts.
//  * Ordinary (Rk4):
//      void drift(t, const State& s, State& f) const;         ds/dt = f
//  * First-order SDE (EulerMaruyamaStepper, Rk4EulerStepper):  ds = f dt + Σ_k g_k dW_k e_{c(k)}
//      State, Noise                                           types (Noise: one column/entry per source)
//      Lanes                                                  one component (scalar, or an Eigen column)
//      static constexpr int noises;                           independent Wiener processes
//      void drift(t, const State& s, State& f) const;
//      void noise(const State& s, Noise& g) const;            amplitude of source k: component<System>(g, k)
//      static constexpr int noise_component(int k);           the component source k drives
//  * Second-order ("mechanical") SDE (BaoabStepper, Taylor15Stepper): components x = 0, y = 1
//      with dx = y dt, dy = b2 dt + σ(x, y) dW₀, and optional linear hidden states z (e.g. an
//      electrical state or a coloured excitation) described by LinearHidden:
//      the first-order members above, plus
//      Lanes sigma(const State& s) const;                     σ = sqrt(a22)
//      double linear_damping() const;                         β of b2 = −β y + (the rest)
//      Lanes force_nl(t, const State& s) const;               b2 + β y (BAOAB's kicks)
//      TaylorDerivatives<Lanes> derivatives(t, s) const;      b2, σ and their partial derivatives
//      bool noise_depends_on_y() const;                       σ depends on y (Taylor's extra terms)
//      static constexpr int hidden;                           number of linear hidden states
//      LinearHidden hidden_state(int i) const;                state i (i < hidden)
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
//                  Leimkuhler–Matthews BAOAB when σ is constant). Hidden states: a noiseless one is
//                  advanced by its exact flow for y frozen over h/2 on either side of O, one with
//                  its own noise (it must not depend on y) by its exact OU step over h in O.
//   Taylor15       Kloeden–Platen strong order-1.5 Itô–Taylor scheme (KP 10.4) written out for
//                  this noise structure:
//                    ΔW = √h ξ₁,  ΔZ = ∫₀ʰ (W_s − W_0) ds = ½ h^{3/2} (ξ₁ + ξ₂/√3)
//                    L⁰f = ∂_t f + y ∂_x f + b2 ∂_y f + ½σ² ∂²_y f (+ hidden drifts · ∂_z f)
//                    X₊ = X + y h + σ ΔZ + ½ b2 h²
//                    Y₊ = Y + b2 h + σ ΔW + σ ∂_y b2 ΔZ + L⁰σ (ΔW h − ΔZ) + ½ L⁰b2 h²
//                         + ½ σσ_y (ΔW² − h) + ½ σ(σ_y² + σσ_yy)(⅓ΔW² − h)ΔW   [σ depends on y]
//                         + Σ c n ΔZ_z                                    [hidden states with noise]
//                    z₊ = z + g h + a_y σ ΔZ + n ΔW_z + a_z n ΔZ_z + ½ (a_y b2 + a_z g) h²,
//                         g = a_y y + a_z z the hidden drift
//                  All mixed multiple integrals I_(j1,j2) with j1 ≠ j2 have zero coefficients
//                  here (σ does not depend on the hidden states; their noise is additive). Strong
//                  1.5 for smooth coefficients; non-smooth terms (sign(y), impact stops) reduce
//                  the order. Where σ = 0 its derivatives are taken as 0.
#include <cmath>
#include <type_traits>

#include <Eigen/Core>

#include "vehs/sim/scheme.hpp"

#if defined(__GNUC__)
#define VEHS_SIM_INLINE inline __attribute__((always_inline))
#else
#define VEHS_SIM_INLINE inline
#endif

namespace vehs::sim {

namespace detail {
template <class T>
inline constexpr bool is_eigen_v = std::is_base_of_v<Eigen::EigenBase<T>, T>;
}  // namespace detail

/// Component c of a state, a noise amplitude or a vector of normals of `System`: column c when
/// the system runs lanes (System::Lanes an Eigen column: trajectories in the rows), entry c when
/// it runs one trajectory (System::Lanes a scalar).
template <class System, class Derived>
VEHS_SIM_INLINE decltype(auto) component(Eigen::DenseBase<Derived>& s, int c) {
  if constexpr (detail::is_eigen_v<typename System::Lanes>)
    return s.derived().col(c);
  else
    return s.derived().coeffRef(c);
}
template <class System, class Derived>
VEHS_SIM_INLINE decltype(auto) component(const Eigen::DenseBase<Derived>& s, int c) {
  if constexpr (detail::is_eigen_v<typename System::Lanes>)
    return s.derived().col(c);
  else
    return s.derived().coeff(c);
}

/// What the order-1.5 Itô–Taylor scheme needs of a mechanical system, per trajectory.
template <class V>
struct TaylorDerivatives {
  V b2, b2_x, b2_y, b2_yy, b2_t;        ///< drift of y and its partial derivatives
  V sigma, sigma_x, sigma_y, sigma_yy;  ///< σ = sqrt(a22) and its partial derivatives
};

/// A linear hidden state z of a mechanical system (component `index`):
///     dz = (a_y·y + a_z·z) dt + n dW_z,   and b2 gains c·z,
/// with a_z < 0 (stable) given through relax(v) = a_z·v so that a system can keep its own
/// arithmetic (a rate λ multiplies, a time constant τ divides). n ≠ 0 requires a_y = 0 and its
/// own noise source `noise_source` of the system. Examples: an electrical state
/// (a_y = 1, a_z = −λ, c = −coupling, n = 0); an Ornstein–Uhlenbeck excitation
/// (a_y = 0, a_z = −1/τ, c = 1, n = sqrt(intensity)/τ, stationary variance intensity/(2τ)).
struct LinearHidden {
  int index = 2;
  double a_y = 0.0;
  double c = 0.0;
  double n = 0.0;
  int noise_source = 1;
  double stationary_variance = 0.0;  ///< n²/(−2 a_z), as the system computes it
  bool by_rate = true;               ///< a_z = −rate (true) or −1/time_constant
  double rate = 0.0, time_constant = 1.0;

  /// a_z·v.
  double relax(double v) const { return by_rate ? -(rate * v) : -(v / time_constant); }
  template <class V>
  V relax(const V& v) const {
    return by_rate ? V(-(rate * v)) : V(-(v / time_constant));
  }
  /// a_z·scale·v.
  template <class V>
  V relax_scaled(double scale, const V& v) const {
    return by_rate ? V(-((rate * scale) * v)) : V(-((scale / time_constant) * v));
  }
};

/// The classical fourth-order Runge–Kutta step of ds/dt = f(t, s) (any state and scalar type).
struct Rk4 {
  template <class System, class State, class Time>
  VEHS_SIM_INLINE void do_step(const System& sys, State& s, Time t, Time h) const {
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
  }
};

/// Adds the Euler increments √h·g_k·ξ_k of every noise source to its component.
template <class System, class State, class Noise, class Xi>
VEHS_SIM_INLINE void add_euler_noise(State& s, const Noise& g, const Xi& xi, double sqh) {
  for (int k = 0; k < System::noises; ++k)
    component<System>(s, System::noise_component(k)) += sqh * component<System>(g, k) * component<System>(xi, k);
}

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
    s += h * f;
    add_euler_noise<System>(s, g, xi, std::sqrt(h));
  }
};

/// The paper's Eq. 30: RK4 on the drift, Euler noise with the amplitude at the start of the step.
struct Rk4EulerStepper {
  static constexpr Scheme scheme = Scheme::Rk4Euler;
  static constexpr int normals_per_source = 1;

  template <class System, class Xi>
  VEHS_SIM_INLINE void step(const System& sys, typename System::State& s, double t, double h,
                            const Xi& xi) const {
    typename System::Noise g;
    sys.noise(s, g);
    Rk4().do_step(sys, s, t, h);
    add_euler_noise<System>(s, g, xi, std::sqrt(h));
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
    const double spread = beta != 0.0 ? std::sqrt(-std::expm1(-2.0 * beta * h) / (2.0 * beta)) : std::sqrt(h);
    component<System>(s, 1) += (0.5 * h) * sys.force_nl(t, s);  // B
    component<System>(s, 0) += (0.5 * h) * component<System>(s, 1);     // A
    hidden_half_flow(sys, s, 0.5 * h);
    const auto sigma = sys.sigma(s);
    component<System>(s, 1) = decay * component<System>(s, 1) + spread * sigma * component<System>(xi, 0);  // O
    hidden_noisy_flow(sys, s, h, xi);
    hidden_half_flow(sys, s, 0.5 * h);
    component<System>(s, 0) += (0.5 * h) * component<System>(s, 1);          // A
    component<System>(s, 1) += (0.5 * h) * sys.force_nl(t + h, s);  // B
  }

 private:
  /// Exact flow of the noiseless hidden states over time h with y frozen.
  template <class System, class State>
  VEHS_SIM_INLINE static void hidden_half_flow(const System& sys, State& s, double h) {
    for (int i = 0; i < System::hidden; ++i) {
      const LinearHidden z = sys.hidden_state(i);
      if (z.n != 0.0) continue;
      const double ah = z.relax(h);  // a_z h
      const double decay = std::exp(ah);
      const double gain = z.a_y * std::expm1(ah) / z.relax(1.0);
      component<System>(s, z.index) = decay * component<System>(s, z.index) + gain * component<System>(s, 1);
    }
  }
  /// Exact Ornstein–Uhlenbeck step over h of the hidden states with their own noise.
  template <class System, class State, class Xi>
  VEHS_SIM_INLINE static void hidden_noisy_flow(const System& sys, State& s, double h, const Xi& xi) {
    for (int i = 0; i < System::hidden; ++i) {
      const LinearHidden z = sys.hidden_state(i);
      if (z.n == 0.0) continue;
      const double ah = z.relax(h);
      const double decay = std::exp(ah);
      const double sd = std::sqrt(z.stationary_variance * -std::expm1(2.0 * ah));
      component<System>(s, z.index) = decay * component<System>(s, z.index) + sd * component<System>(xi, z.noise_source);
    }
  }
};

struct Taylor15Stepper {
  static constexpr Scheme scheme = Scheme::Taylor15;
  static constexpr int normals_per_source = 2;

  template <class System, class Xi>
  VEHS_SIM_INLINE void step(const System& sys, typename System::State& s, double t, double h,
                            const Xi& xi) const {
    using Lanes = typename System::Lanes;
    const auto j = sys.derivatives(t, s);
    const double sqh = std::sqrt(h), h2 = h * h;
    const Lanes dW = sqh * component<System>(xi, 0);
    const Lanes dZ = (0.5 * h * sqh) * (component<System>(xi, 0) + component<System>(xi, 1) * (1.0 / std::sqrt(3.0)));
    const Lanes y = component<System>(s, 1);
    const Lanes sig2 = j.sigma * j.sigma;
    Lanes L0b2 = j.b2_t + y * j.b2_x + j.b2 * j.b2_y + 0.5 * sig2 * j.b2_yy;
    const Lanes L0sigma = y * j.sigma_x + j.b2 * j.sigma_y + 0.5 * sig2 * j.sigma_yy;
    // hidden drifts g = a_y y + a_z z, and their part of L⁰b2
    Lanes g[System::hidden > 0 ? System::hidden : 1];
    for (int i = 0; i < System::hidden; ++i) {
      const LinearHidden z = sys.hidden_state(i);
      const Lanes zi = component<System>(s, z.index);
      g[i] = z.a_y != 0.0 ? Lanes(z.a_y * y + z.relax(zi)) : z.relax(zi);
      L0b2 += z.c * g[i];
    }
    Lanes dy = j.b2 * h + j.sigma * dW + j.sigma * j.b2_y * dZ + L0sigma * (dW * h - dZ) + (0.5 * h2) * L0b2;
    if (sys.noise_depends_on_y()) {
      const Lanes dW2 = dW * dW;
      dy += 0.5 * j.sigma * j.sigma_y * (dW2 - h) +
            0.5 * j.sigma * (j.sigma_y * j.sigma_y + j.sigma * j.sigma_yy) * (dW2 * (1.0 / 3.0) - h) * dW;
    }
    for (int i = 0; i < System::hidden; ++i) {
      const LinearHidden z = sys.hidden_state(i);
      Lanes dz = g[i] * h;
      if (z.a_y != 0.0) dz += (z.a_y * j.sigma) * dZ;
      if (z.n != 0.0) {
        const Lanes dWz = sqh * component<System>(xi, 2 * z.noise_source);
        const Lanes dZz = (0.5 * h * sqh) * (component<System>(xi, 2 * z.noise_source) +
                                             component<System>(xi, 2 * z.noise_source + 1) * (1.0 / std::sqrt(3.0)));
        dy += (z.c * z.n) * dZz;
        dz += z.n * dWz;
        dz += z.relax(z.n) * dZz;
      }
      // ½ (a_y b2 + a_z g) h²
      const Lanes second = z.a_y != 0.0 ? Lanes((0.5 * h2) * (z.a_y * j.b2 + z.relax(g[i])))
                                        : z.relax_scaled(0.5 * h2, g[i]);
      component<System>(s, z.index) += dz + second;
    }
    component<System>(s, 0) += y * h + j.sigma * dZ + (0.5 * h2) * j.b2;
    component<System>(s, 1) += dy;
  }
};

}  // namespace vehs::sim
