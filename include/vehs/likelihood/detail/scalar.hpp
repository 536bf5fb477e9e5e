#pragma once
// The value part of a scalar that may carry derivatives (double or ceres::Jet).
#include <ceres/jet.h>

namespace vehs::likelihood::detail {

inline double value_of(double x) { return x; }
template <class T, int N>
double value_of(const ceres::Jet<T, N>& j) {
  return value_of(j.a);
}

}  // namespace vehs::likelihood::detail
