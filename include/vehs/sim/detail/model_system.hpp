#pragma once
// Internal: the harvester model SDE as a mechanical system for the steppers of
// vehs/sim/steppers.hpp, compiled once from a vehs::Model (CompiledModel), in two forms: the
// general ModelSystem (any terms, every dynamic effect) and the compile-time-shaped
// PolynomialSystem for the paper's polynomial family (the simulator's fast path).
//
// State (one column per component, one row per SIMD lane = one record):
//     column 0: x (displacement), 1: y (velocity),
//     then, when the model has them, the hidden states of dynamic effects:
//     v (electromechanical_coupling: dv = (y − λ·v) dt, force −coupling·v) and
//     η (colored_noise: dη = −η/τ dt + sqrt(intensity)/τ dW₂, force +η).
// Dynamics (Itô, docs/model-file.md plus the catalogue of src/core/model.cpp):
//     dx = y dt
//     dy = b2(t, x, y, u, v, η) dt + σ(x, y) dW₁,   σ = sqrt(a22(x, y))
// with b2 = Σ coef·term(x, y, u) + stop force (vehs/effects/impact_stop.hpp)
//           + harmonic force (vehs/effects/harmonic_forcing.hpp) − coupling·v + η.
// Noise sources: W₁ acts on y with amplitude σ(x, y); W₂ (coloured noise only) acts on η with
// the constant amplitude sqrt(intensity)/τ. σ never depends on v, η or t, and the η noise is
// additive, so all mixed multiple Itô integrals of the order-1.5 scheme vanish (see steppers.hpp).
//
// Both systems model the mechanical-system concept of steppers.hpp (lanes: L records advanced
// in lockstep, V = Lanes); v and η are its linear hidden states (LinearHidden). Time t is
// common to all lanes. A recorded drive u is held constant over each recorded interval
// (zero-order hold, like a DAC) and set per interval with set_drive().
//
// a22 < 0 anywhere makes σ = NaN; the simulator catches that as a non-finite state (the
// configuration checks reject models whose a22 is negative in the region of interest).
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vehs/core/model.hpp"
#include "vehs/effects/harmonic_forcing.hpp"
#include "vehs/effects/impact_stop.hpp"
#include "vehs/sim/steppers.hpp"

namespace vehs::sim::detail {

/// A polynomial Σ c_n xⁿ, evaluated by Horner's rule in x² on its even and odd parts
/// (halves the dependency chain of odd or even potentials).
struct XPolynomial {
  std::vector<double> even;  ///< even[k] = c_{2k}
  std::vector<double> odd;   ///< odd[k] = c_{2k+1}

  /// From dense coefficients c[n] of xⁿ (trailing zeros trimmed, zero parts left empty).
  static XPolynomial from_coefficients(const std::vector<double>& c);
  std::vector<double> coefficients() const;
  XPolynomial derivative() const;
  bool empty() const { return even.empty() && odd.empty(); }
  int degree() const;  ///< −1 when empty
  double leading_coefficient() const;

  /// Value on lanes; x2 = x·x.
  template <class V>
  V eval(const V& x, const V& x2) const {
    if (odd.empty()) {
      if (even.empty()) return V::Zero(x.rows(), x.cols());
      return horner(even, x2);
    }
    if (even.empty()) return x * horner(odd, x2);
    return horner(even, x2) + x * horner(odd, x2);
  }
  /// Σ c[k]·z^k by Horner's rule. Up to 12 coefficients the steps are a straight-line
  /// fall-through sequence (no loop), so the lanes stay in registers.
  template <class V>
  static V horner(const std::vector<double>& c, const V& z) {
    const double* p = c.data();
    const int n = static_cast<int>(c.size());
    if (n > 12) {
      V r = V::Constant(z.rows(), z.cols(), p[n - 1]);
      for (int k = n - 2; k >= 0; --k) r = r * z + p[k];
      return r;
    }
    V r = V::Constant(z.rows(), z.cols(), p[n - 1]);
    switch (n) {
      case 12: r = r * z + p[10]; [[fallthrough]];
      case 11: r = r * z + p[9]; [[fallthrough]];
      case 10: r = r * z + p[8]; [[fallthrough]];
      case 9: r = r * z + p[7]; [[fallthrough]];
      case 8: r = r * z + p[6]; [[fallthrough]];
      case 7: r = r * z + p[5]; [[fallthrough]];
      case 6: r = r * z + p[4]; [[fallthrough]];
      case 5: r = r * z + p[3]; [[fallthrough]];
      case 4: r = r * z + p[2]; [[fallthrough]];
      case 3: r = r * z + p[1]; [[fallthrough]];
      case 2: r = r * z + p[0]; [[fallthrough]];
      default: break;
    }
    return r;
  }
  double eval(double x) const;
};

/// Σ_j y^j·P_j(x) + c₁·y|y| + c₂·|y| + c₃·sign(y) + c₄·u: the term part of b2 or a22 (or of
/// one of their partial derivatives) grouped by powers of y.
struct YXPolynomial {
  std::vector<XPolynomial> by_ypow;  ///< by_ypow[j] multiplies y^j (trailing empties trimmed)
  double y_abs_y = 0.0;              ///< coefficient of y·|y|
  double abs_y = 0.0;                ///< coefficient of |y| (appears in ∂_y of y·|y|)
  double sign_y = 0.0;               ///< coefficient of sign(y), sign(0) = 0
  double drive = 0.0;                ///< coefficient of u (drift only)
  /// A user's expression term (or one of its partial derivatives, by central differences).
  struct UserPart {
    double coef = 0.0;
    Term term;
    enum Of { Value, Dx, Dy, Dyy } of = Value;
    double at(double x, double y, double u) const {
      switch (of) {
        case Dx: return coef * term.d_dx(x, y, u);
        case Dy: return coef * term.d_dy(x, y, u);
        case Dyy: return coef * term.d2_dy2(x, y, u);
        default: return coef * term.value(x, y, u);
      }
    }
  };
  std::vector<UserPart> user;
  bool has_nonpoly = false;          ///< any of y_abs_y, abs_y, sign_y, user is non-zero

  int max_ypow() const { return static_cast<int>(by_ypow.size()) - 1; }
  bool depends_on_y() const {
    bool user_y = false;
    for (const auto& p : user) user_y = user_y || p.term.depends_on_y();
    return by_ypow.size() > 1 || y_abs_y != 0.0 || abs_y != 0.0 || sign_y != 0.0 || user_y;
  }
  /// Scalar evaluation (checks, tests).
  double eval(double x, double y, double u = 0.0) const;
};

/// Everything a ModelSystem needs, extracted once from a vehs::Model (validated there).
struct CompiledModel {
  YXPolynomial drift, diffusion;
  YXPolynomial drift_dx, drift_dy, drift_dyy;          ///< term derivatives (Taylor scheme)
  YXPolynomial diffusion_dx, diffusion_dy, diffusion_dyy;
  double beta = 0.0;  ///< −drift["y"], the linear damping split off by BAOAB
  bool additive_noise = false;  ///< a22 is a constant
  double constant_sigma = 0.0;  ///< sqrt(a22) when additive
  bool noise_depends_on_y = false;
  // dynamic effects
  bool impact = false;
  effects::ImpactStop<double> stop;
  bool harmonic = false;
  effects::HarmonicForcing<double> forcing;
  bool electro = false;
  double lambda = 0.0, coupling = 0.0;
  bool colored = false;
  double tau = 0.0, intensity = 0.0;
  /// Anything beyond the polynomial drift (drive, stops, forcing, hidden states): one branch
  /// skips all of it on the fast path.
  bool has_extras = false;

  /// The polynomial family of the paper's dictionaries, integrated by PolynomialSystem with
  /// compile-time shapes: b2 = P(x) + y·(c0 + c1 x + c2 x²) with deg P ≤ 11, a22 = A(x) with
  /// deg A ≤ 4, no other terms and no dynamic effects. Coefficients are zero-padded.
  struct Fast {
    bool eligible = false;
    int k = 0;  ///< P has even and odd parts of k coefficients each (deg P ≤ 2k − 1), 1 ≤ k ≤ 6
    std::array<double, 6> even{}, odd{};    ///< P(x) = E(x²) + x·O(x²)
    std::array<double, 6> deven{}, dodd{};  ///< P'(x) likewise
    std::array<double, 3> damping{};        ///< c0, c1, c2
    std::array<double, 5> a22{};            ///< A(x) = Σ a_n xⁿ
    std::array<double, 5> da22{};           ///< A'(x)
    bool has_even = false;                  ///< P has even powers
    bool damping_poly = false;              ///< c1 or c2 non-zero
    bool a22_even2 = false;                 ///< A(x) = a0 + a2 x²
    bool additive = false;                  ///< A constant
    double sigma0 = 0.0;                    ///< sqrt(a0) when additive
  } fast;

  /// Builds the compiled form; throws vehs::Error (prefixed with `where`) for models the
  /// simulator cannot represent.
  static CompiledModel from_model(const Model& m, const std::string& where);
  /// Standard deviation of the stationary η: sqrt(intensity / (2τ)).
  double colored_stationary_sd() const { return colored ? std::sqrt(intensity / (2.0 * tau)) : 0.0; }
};

/// The general system: any term list and every dynamic effect, evaluated with run-time
/// dispatch (it need not be as fast as PolynomialSystem; it is compiled with ordinary inlining
/// to keep build times down).
template <int L, bool kElectro, bool kColored>
class ModelSystem {
 public:
  static constexpr int lanes = L;
  static constexpr int electro_index = 2;
  static constexpr int colored_index = 2 + (kElectro ? 1 : 0);
  static constexpr int dim = 2 + (kElectro ? 1 : 0) + (kColored ? 1 : 0);
  static constexpr int noises = kColored ? 2 : 1;
  static constexpr bool has_electro = kElectro;
  static constexpr bool has_colored = kColored;
  static constexpr int hidden = (kElectro ? 1 : 0) + (kColored ? 1 : 0);
  using Lanes = Eigen::Array<double, L, 1>;
  using State = Eigen::Array<double, L, dim>;
  using Noise = Eigen::Array<double, L, noises>;

  /// Copies what it needs of `m` (a system never refers to a model that may go away).
  explicit ModelSystem(const CompiledModel& m) : m_(m), u_(Lanes::Zero()) {
    int i = 0;
    if constexpr (kElectro) {
      LinearHidden& v = hidden_[i++];
      v.index = electro_index;
      v.a_y = 1.0;
      v.c = -m_.coupling;
      v.by_rate = true;
      v.rate = m_.lambda;
    }
    if constexpr (kColored) {
      LinearHidden& eta = hidden_[i++];
      eta.index = colored_index;
      eta.c = 1.0;
      eta.n = std::sqrt(m_.intensity) / m_.tau;
      eta.noise_source = 1;
      eta.stationary_variance = m_.intensity / (2.0 * m_.tau);
      eta.by_rate = false;
      eta.time_constant = m_.tau;
    }
    (void)i;
  }

  /// Drive values of the current recorded interval, one per lane.
  void set_drive(const Lanes& u) { u_ = u; }
  LinearHidden hidden_state(int i) const { return hidden_[static_cast<std::size_t>(i)]; }
  bool noise_depends_on_y() const { return m_.noise_depends_on_y; }

  static constexpr int noise_component(int k) { return k == 0 ? 1 : colored_index; }

  /// b2 on lanes.
  Lanes b2(double t, const State& s) const {
    const Lanes x = s.col(0), y = s.col(1);
    const Lanes x2 = x * x;
    Lanes r = poly_y(m_.drift, x, x2, y);
    add_nonpoly(r, t, s, x);
    return r;
  }

  void drift(double t, const State& s, State& f) const {
    f.col(0) = s.col(1);
    f.col(1) = b2(t, s);
    if constexpr (kElectro) f.col(electro_index) = s.col(1) - m_.lambda * s.col(electro_index);
    if constexpr (kColored) f.col(colored_index) = -s.col(colored_index) / m_.tau;
  }

  Lanes sigma(const State& s) const {
    if (m_.additive_noise) return Lanes::Constant(m_.constant_sigma);
    const Lanes x = s.col(0), y = s.col(1);
    const Lanes x2 = x * x;
    return poly_y(m_.diffusion, x, x2, y).sqrt();
  }

  void noise(const State& s, Noise& g) const {
    g.col(0) = sigma(s);
    if constexpr (kColored) g.col(1) = Lanes::Constant(std::sqrt(m_.intensity) / m_.tau);
  }

  double linear_damping() const { return m_.beta; }
  /// b2 + β·y: the force BAOAB applies in its kicks.
  Lanes force_nl(double t, const State& s) const { return b2(t, s) + m_.beta * s.col(1); }

  TaylorDerivatives<Lanes> derivatives(double t, const State& s) const {
    TaylorDerivatives<Lanes> j;
    const Lanes x = s.col(0), y = s.col(1);
    const Lanes x2 = x * x;
    j.b2 = poly_y(m_.drift, x, x2, y);
    add_nonpoly(j.b2, t, s, x);
    j.b2_x = poly_y(m_.drift_dx, x, x2, y);
    if (m_.impact) j.b2_x += m_.stop.force_dx(x);
    j.b2_y = poly_y(m_.drift_dy, x, x2, y);
    j.b2_yy = poly_y(m_.drift_dyy, x, x2, y);
    j.b2_t = m_.harmonic ? Lanes::Constant(m_.forcing.force_dt(t)) : Lanes::Zero();
    if (m_.additive_noise) {
      j.sigma = Lanes::Constant(m_.constant_sigma);
      j.sigma_x = j.sigma_y = j.sigma_yy = Lanes::Zero();
      return j;
    }
    const Lanes a = poly_y(m_.diffusion, x, x2, y);
    j.sigma = a.sqrt();
    // σ_x = a_x / (2σ) etc.; where σ = 0 the derivatives are set to 0 (documented limitation)
    const Lanes inv2s = (j.sigma > 0.0).select(0.5 / j.sigma, 0.0);
    j.sigma_x = poly_y(m_.diffusion_dx, x, x2, y) * inv2s;
    if (m_.noise_depends_on_y) {
      const Lanes a_y = poly_y(m_.diffusion_dy, x, x2, y);
      j.sigma_y = a_y * inv2s;
      j.sigma_yy = (poly_y(m_.diffusion_dyy, x, x2, y) - 2.0 * j.sigma_y * j.sigma_y) * inv2s;
    } else {
      j.sigma_y = j.sigma_yy = Lanes::Zero();
    }
    return j;
  }

 private:
  Lanes poly_y(const YXPolynomial& p, const Lanes& x, const Lanes& x2, const Lanes& y) const {
    const int J = p.max_ypow();
    Lanes r;
    if (J < 0) {
      r = Lanes::Zero();
    } else if (J == 1 && p.by_ypow[1].odd.empty() && p.by_ypow[1].even.size() == 1) {
      r = p.by_ypow[0].eval(x, x2) + p.by_ypow[1].even[0] * y;  // P0(x) + c·y (the paper's form)
    } else {
      r = p.by_ypow[static_cast<std::size_t>(J)].eval(x, x2);
      for (int jj = J - 1; jj >= 0; --jj) r = r * y + p.by_ypow[static_cast<std::size_t>(jj)].eval(x, x2);
    }
    if (p.has_nonpoly) {
      if (p.y_abs_y != 0.0) r += p.y_abs_y * y * y.abs();
      if (p.abs_y != 0.0) r += p.abs_y * y.abs();
      if (p.sign_y != 0.0)
        r += p.sign_y * ((y > 0.0).template cast<double>() - (y < 0.0).template cast<double>());
      for (const auto& part : p.user)
        for (int l = 0; l < L; ++l) r[l] += part.at(x[l], y[l], u_[l]);
    }
    return r;
  }

  void add_nonpoly(Lanes& r, double t, const State& s, const Lanes& x) const {
    if (!m_.has_extras) return;
    if (m_.drift.drive != 0.0) r += m_.drift.drive * u_;  // held over the interval: ∂_t = 0
    if (m_.impact) r += m_.stop.force(x);
    if (m_.harmonic) r += m_.forcing.force(t);
    if constexpr (kElectro) r -= m_.coupling * s.col(electro_index);
    if constexpr (kColored) r += s.col(colored_index);
    (void)s;
    (void)t;
  }

  CompiledModel m_;
  Lanes u_;
  std::array<LinearHidden, 2> hidden_{};
};

/// Eigen's arrays as the lanes of a system (the default of PolynomialSystem).
template <int L>
struct EigenLanes {
  using Lanes = Eigen::Array<double, L, 1>;
  using State = Eigen::Array<double, L, 2>;
  using Noise = Eigen::Array<double, L, 1>;
};

/// The fast system for the polynomial family (CompiledModel::Fast): the same concept as
/// ModelSystem, with every polynomial of compile-time length K (even and odd parts of P), 3
/// (damping) and 5 (a22), so the lanes stay in registers and nothing is dispatched at run time.
/// `Types` gives the lane, state and noise types: Eigen's arrays, or the lane type of the
/// simulator's per-instruction-set kernels (src/sim/simd/lanes.hpp), which run this system.
template <int L, int K, class Types = EigenLanes<L>>
class PolynomialSystem {
 public:
  static constexpr int lanes = L;
  static constexpr int electro_index = 2;
  static constexpr int colored_index = 2;
  static constexpr int dim = 2;
  static constexpr int noises = 1;
  static constexpr bool has_electro = false;
  static constexpr bool has_colored = false;
  static constexpr int hidden = 0;
  using Lanes = typename Types::Lanes;
  using State = typename Types::State;
  using Noise = typename Types::Noise;

  explicit PolynomialSystem(const CompiledModel& m) : f_(m.fast) {}
  explicit PolynomialSystem(const CompiledModel::Fast& f) : f_(f) {}
  void set_drive(const Lanes&) {}
  LinearHidden hidden_state(int) const { return {}; }
  static constexpr bool noise_depends_on_y() { return false; }
  static constexpr int noise_component(int) { return 1; }

  template <std::size_t N>
  static VEHS_SIM_INLINE Lanes horner(const std::array<double, 6>& c, const Lanes& z) {
    Lanes r = Lanes::Constant(c[N - 1]);
    for (int k = static_cast<int>(N) - 2; k >= 0; --k) r = r * z + c[static_cast<std::size_t>(k)];
    return r;
  }
  // Parts that are zero for a model are skipped by branches that are the same for every step
  // (perfectly predicted): an odd potential needs no even part, linear damping no polynomial,
  // additive noise no square root.
  VEHS_SIM_INLINE Lanes restoring(const Lanes& x, const Lanes& x2) const {
    if (f_.has_even) return horner<K>(f_.even, x2) + x * horner<K>(f_.odd, x2);
    return x * horner<K>(f_.odd, x2);
  }
  VEHS_SIM_INLINE Lanes damping(const Lanes& x) const {
    if (f_.damping_poly) return (f_.damping[2] * x + f_.damping[1]) * x + f_.damping[0];
    return Lanes::Constant(f_.damping[0]);
  }
  VEHS_SIM_INLINE Lanes a22(const Lanes& x) const {
    if (f_.a22_even2) return f_.a22[2] * x * x + f_.a22[0];
    return (((f_.a22[4] * x + f_.a22[3]) * x + f_.a22[2]) * x + f_.a22[1]) * x + f_.a22[0];
  }

  VEHS_SIM_INLINE Lanes b2(double, const State& s) const {
    const Lanes x = s.col(0);
    if (f_.damping_poly) return restoring(x, x * x) + damping(x) * s.col(1);
    return restoring(x, x * x) + f_.damping[0] * s.col(1);
  }
  VEHS_SIM_INLINE void drift(double t, const State& s, State& f) const {
    f.col(0) = s.col(1);
    f.col(1) = b2(t, s);
  }
  VEHS_SIM_INLINE Lanes sigma(const State& s) const {
    if (f_.additive) return Lanes::Constant(f_.sigma0);
    return a22(s.col(0)).sqrt();
  }
  VEHS_SIM_INLINE void noise(const State& s, Noise& g) const { g.col(0) = sigma(s); }
  double linear_damping() const { return -f_.damping[0]; }
  VEHS_SIM_INLINE Lanes force_nl(double t, const State& s) const { return b2(t, s) - f_.damping[0] * s.col(1); }
  VEHS_SIM_INLINE TaylorDerivatives<Lanes> derivatives(double, const State& s) const {
    TaylorDerivatives<Lanes> j;
    const Lanes x = s.col(0), y = s.col(1);
    const Lanes x2 = x * x;
    const Lanes c = damping(x);
    j.b2 = restoring(x, x2) + c * y;
    j.b2_x = horner<K>(f_.deven, x2) + x * horner<K>(f_.dodd, x2) + (2.0 * f_.damping[2] * x + f_.damping[1]) * y;
    j.b2_y = c;
    j.b2_yy = Lanes::Zero();
    j.b2_t = Lanes::Zero();
    j.sigma = a22(x).sqrt();
    const Lanes da = (((4.0 * f_.a22[4] * x + 3.0 * f_.a22[3]) * x + 2.0 * f_.a22[2]) * x + f_.a22[1]);
    j.sigma_x = (j.sigma > 0.0).select(da * (0.5 / j.sigma), 0.0);
    j.sigma_y = Lanes::Zero();
    j.sigma_yy = Lanes::Zero();
    return j;
  }

 private:
  CompiledModel::Fast f_;  ///< by value: a local copy of the system keeps them in registers
};

}  // namespace vehs::sim::detail
