#pragma once
// A small fixed-step ODE propagator generic over the state and scalar type: classical RK4 over
// `substeps` equal steps of an interval. The state is any type with `+`, `-` and
// multiplication by a double (Eigen fixed-size vectors of double or ceres::Jet), so the same
// code propagates plain trajectories (free-run simulation) and moment equations carrying
// derivatives (the likelihood's automatic differentiation).
//
// The right-hand side is `bool rhs(double t, const State& s, State& ds)`; it returns false when
// the state has left the region where the equations are defined (the step then stops and
// propagate returns false). Time is always double: nothing is differentiated with respect to
// it. (Written so that it can be swapped for the project's generic stepper once the steppers
// are generic over system, state and scalar type.)
#include "vehs/likelihood/detail/flatten.hpp"

namespace vehs::likelihood {

namespace detail {
/// out = s + a·k, element by element with compound operators (no scalar temporaries: with
/// ceres::Jet every temporary is a vector of derivatives).
template <class State>
void rk4_stage(const State& s, double a, const State& k, State& out) {
  for (decltype(s.size()) j = 0; j < s.size(); ++j) {
    out[j] = k[j];
    out[j] *= a;
    out[j] += s[j];
  }
}
/// acc += a·k, element by element.
template <class State>
void rk4_accumulate(double a, const State& k, State& acc) {
  for (decltype(acc.size()) j = 0; j < acc.size(); ++j) {
    auto v = k[j];
    v *= a;
    acc[j] += v;
  }
}
}  // namespace detail

template <class State, class Rhs>
VEHS_FLATTEN bool rk4_propagate(const Rhs& rhs, double t0, double duration, int substeps, State& s) {
  const double h = duration / substeps;
  State k, stage, next;
  for (int i = 0; i < substeps; ++i) {
    const double t = t0 + i * h;
    // next = s + h/6 (k1 + 2 k2 + 2 k3 + k4), accumulated stage by stage
    if (!rhs(t, s, k)) return false;
    next = s;
    detail::rk4_accumulate(h / 6.0, k, next);
    detail::rk4_stage(s, 0.5 * h, k, stage);
    if (!rhs(t + 0.5 * h, stage, k)) return false;
    detail::rk4_accumulate(h / 3.0, k, next);
    detail::rk4_stage(s, 0.5 * h, k, stage);
    if (!rhs(t + 0.5 * h, stage, k)) return false;
    detail::rk4_accumulate(h / 3.0, k, next);
    detail::rk4_stage(s, h, k, stage);
    if (!rhs(t + h, stage, k)) return false;
    detail::rk4_accumulate(h / 6.0, k, next);
    s = next;
  }
  return true;
}

}  // namespace vehs::likelihood
