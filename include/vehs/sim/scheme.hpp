#pragma once
// The integration schemes of the simulator (vehs/sim/steppers.hpp implements them).
#include "vehs/core/enum_names.hpp"

namespace vehs::sim {

enum class Scheme {
  EulerMaruyama,  ///< strong order 1 for this noise structure
  Rk4Euler,       ///< the paper's Eq. 30: RK4 on the drift + Euler noise on Y
  Baoab,          ///< BAOAB splitting (kick, drift, exact OU for linear damping, drift, kick)
  Taylor15,       ///< Kloeden–Platen strong order 1.5 Itô–Taylor scheme
};
inline constexpr EnumNames<Scheme, 4> kSchemeNames{{{Scheme::EulerMaruyama, "euler_maruyama"},
                                                     {Scheme::Rk4Euler, "rk4_euler"},
                                                     {Scheme::Baoab, "baoab"},
                                                     {Scheme::Taylor15, "taylor15"}}};

}  // namespace vehs::sim
