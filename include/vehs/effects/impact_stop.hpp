#pragma once
// impact_stop: end stops of stiffness k_stop at x = gap and x = −gap_neg. This header is the
// one place the stops' physics is written; the simulator, the likelihood filter, the free run,
// diagnose's lens, the stationary FPK and identify's fits all evaluate it from here.
//
//     force(x) = −k_stop·(x − gap)⁺ + k_stop·(−x − gap_neg)⁺
//     U(x)     = ½·k_stop·[(x − gap)⁺² + (−x − gap_neg)⁺²]          (force = −U′)
#include <array>
#include <cmath>
#include <cstddef>
#include <string_view>

#include "vehs/effects/param.hpp"
#include "vehs/effects/piecewise.hpp"
#include "vehs/likelihood/detail/gaussian_expectations.hpp"

namespace vehs::effects {

template <class T>
struct ImpactStop {
  T k_stop{}, gap{}, gap_neg{};

  static constexpr std::string_view name = "impact_stop";
  static constexpr std::string_view physics =
      "end stops: force −k_stop·(x − gap) for x > gap and −k_stop·(x + gap_neg) for x < −gap_neg";

  using Param = effects::Param<ImpactStop, T>;
  static inline const std::array<Param, 3> params{{
      {"k_stop", "stiffness of the stops", 0.0, true, std::nullopt, {0, -2}, &ImpactStop::k_stop},
      {"gap", "distance from x = 0 to the positive stop", 0.0, true, std::nullopt, {1, 0}, &ImpactStop::gap},
      {"gap_neg", "distance to the negative stop (default: gap)", 0.0, true, std::nullopt, {1, 0},
       &ImpactStop::gap_neg},
  }};

  /// From named values (get(name) returns the value or nullopt); gap_neg defaults to gap.
  template <class Get>
  static ImpactStop from(Get&& get) {
    ImpactStop s;
    s.k_stop = T(get("k_stop").value_or(0.0));
    s.gap = T(get("gap").value_or(0.0));
    s.gap_neg = T(get("gap_neg").value_or(s.gap));
    return s;
  }

  /// The force on the mass at displacement x (x: T, or Eigen lanes when T is double).
  template <class X>
  X force(const X& x) const {
    return k_stop * (positive_part(X(-x - gap_neg)) - positive_part(X(x - gap)));
  }
  /// ∂force/∂x.
  template <class X>
  X force_dx(const X& x) const {
    return -k_stop * (step(X(x - gap)) + step(X(-x - gap_neg)));
  }
  /// The potential U with force = −U′, U(0) = 0.
  T potential(const T& x) const {
    const T p = positive_part(T(x - gap)), n = positive_part(T(-x - gap_neg));
    return 0.5 * k_stop * (p * p + n * n);
  }
  /// The largest |∂force/∂x| (step-size rules) and the stiffness the stops add for |x| → ∞
  /// (confinement): both k_stop.
  T stiffness() const { return k_stop; }

  /// Beyond each stop the force is affine, force = slope·x + offset: {x > gap, x < −gap_neg}.
  struct Affine {
    T slope, offset;
  };
  std::array<Affine, 2> outer_pieces() const { return {{{-k_stop, k_stop * gap}, {-k_stop, -k_stop * gap_neg}}}; }

  struct Expectation {
    T force, force_dx;
  };
  /// E[force(X)] and E[∂force/∂x(X)] for X ~ N(mean, sd²), in closed form.
  Expectation expectation(const T& mean, const T& sd) const {
    using likelihood::detail::expect_hinge;
    using likelihood::detail::expect_step;
    const T neg = -mean;
    return {k_stop * (expect_hinge(neg, sd, gap_neg) - expect_hinge(mean, sd, gap)),
            -k_stop * (expect_step(mean, sd, gap) + expect_step(neg, sd, gap_neg))};
  }
};

/// The force shape of the stops with k_stop = 1, −(x − gap)⁺ + (−x − gap_neg)⁺, at every sample
/// of a record (identify's linear column); with tent_k > 0 its average over the kernel of the
/// central second difference at stride tent_k (weights (k − |s|)/k² over s ∈ [−k, k] samples, x
/// linear between samples), which is what the ULI acceleration measures of a force that is not
/// smooth in time.
void impact_stop_record_shape(const double* x, std::size_t n, double gap, double gap_neg, int tent_k,
                              double* out);
/// Adds the stops' force along a record, k_stop times the shape above, to out[0 … n).
void add_impact_stop_record_force(const ImpactStop<double>& stop, const double* x, std::size_t n, int tent_k,
                                  double* out);

}  // namespace vehs::effects
