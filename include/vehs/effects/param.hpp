#pragma once
// One parameter of an effect type E<T>: its name, meaning, domain, default, unit and the member
// that holds it (so that code generic over effects reads and writes parameters by name).
#include <optional>
#include <string_view>

#include "vehs/effects/unit_powers.hpp"

namespace vehs::effects {

template <class E, class T>
struct Param {
  std::string_view name, meaning;
  double lower_bound;  ///< the value must be >= this (−inf when free)
  bool strictly_positive;
  std::optional<double> default_value;  ///< absent: required
  UnitPowers unit;
  T E::*member;
};

}  // namespace vehs::effects
