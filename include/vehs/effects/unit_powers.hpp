#pragma once
// The physical dimension of an effect parameter as powers of the data's length L and time T
// (the change of units of vehs/core/scaling.hpp multiplies by L^length · T^time).
#include <cmath>

namespace vehs::effects {

struct UnitPowers {
  int length = 0;
  int time = 0;

  /// L^length · T^time.
  double scale(double L, double T) const { return std::pow(L, length) * std::pow(T, time); }
};

}  // namespace vehs::effects
