#pragma once
// The kinks that non-smooth effects are made of — the positive part z⁺ = max(z, 0) and the
// step 1[z > 0] — for every scalar an effect is evaluated on: double, ceres::Jet (derivatives
// for the likelihood) and Eigen arrays (the simulator's SIMD lanes).
#include <type_traits>

#include <Eigen/Core>

namespace vehs::effects {

namespace detail {
template <class X>
constexpr bool is_array = std::is_base_of_v<Eigen::ArrayBase<X>, X>;
}  // namespace detail

/// z⁺ = max(z, 0).
template <class X>
X positive_part(const X& z) {
  if constexpr (detail::is_array<X>) return z.max(0.0);
  else return z > 0.0 ? z : X(0.0);
}

/// 1[z > 0] (the derivative of z⁺; 0 at the kink).
template <class X>
X step(const X& z) {
  if constexpr (detail::is_array<X>) return (z > 0.0).template cast<double>();
  else return z > 0.0 ? X(1.0) : X(0.0);
}

}  // namespace vehs::effects
