#pragma once
// An effect type (vehs/effects/) with the parameter values of a model's Effect entry.
#include <optional>
#include <string>
#include <string_view>

#include "vehs/core/model.hpp"

namespace vehs::effects {

/// E<T> built from the named parameters of `e` (absent ones take the type's defaults).
template <template <class> class E, class T = double>
E<T> from_effect(const Effect& e) {
  return E<T>::from([&](std::string_view key) -> std::optional<double> {
    auto it = e.params.find(std::string(key));
    if (it == e.params.end()) return std::nullopt;
    return it->second;
  });
}

/// The catalogue entry (vehs/core/model.hpp) of an effect type.
template <template <class> class E>
EffectSpec spec_of(EffectId id, bool term_like = false) {
  EffectSpec s{id, E<double>::name, E<double>::physics, term_like, {}};
  for (const auto& p : E<double>::params)
    s.params.push_back({p.name, p.meaning, p.lower_bound, p.strictly_positive, p.default_value});
  return s;
}

/// The unit scale L^a·T^b of parameter `key` of E (0 when E has no such parameter).
template <template <class> class E>
double unit_scale_of(std::string_view key, double L, double T) {
  for (const auto& p : E<double>::params)
    if (p.name == key) return p.unit.scale(L, T);
  return 0.0;
}

}  // namespace vehs::effects
