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
namespace vehs::likelihood {

template <class State, class Rhs>
bool rk4_propagate(const Rhs& rhs, double t0, double duration, int substeps, State& s) {
  const double h = duration / substeps;
  State k1, k2, k3, k4;
  for (int i = 0; i < substeps; ++i) {
    const double t = t0 + i * h;
    if (!rhs(t, s, k1)) return false;
    if (!rhs(t + 0.5 * h, State(s + (0.5 * h) * k1), k2)) return false;
    if (!rhs(t + 0.5 * h, State(s + (0.5 * h) * k2), k3)) return false;
    if (!rhs(t + h, State(s + h * k3), k4)) return false;
    s += (h / 6.0) * (k1 + 2.0 * (k2 + k3) + k4);
  }
  return true;
}

}  // namespace vehs::likelihood
