#pragma once
// harmonic_forcing: a periodic force amplitude·cos(omega·t + phase). This header is the one
// place its physics is written; the simulator, the likelihood filter, the free run, diagnose's
// lens and identify's fits evaluate it from here.
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string_view>

#include "vehs/effects/param.hpp"

namespace vehs::effects {

template <class T>
struct HarmonicForcing {
  T amplitude{}, omega{}, phase{};

  static constexpr std::string_view name = "harmonic_forcing";
  static constexpr std::string_view physics = "force amplitude·cos(omega·t + phase)";

  using Param = effects::Param<HarmonicForcing, T>;
  static inline const std::array<Param, 3> params{{
      {"amplitude", "forcing amplitude", 0.0, false, std::nullopt, {1, -2}, &HarmonicForcing::amplitude},
      {"omega", "angular frequency", 0.0, true, std::nullopt, {0, -1}, &HarmonicForcing::omega},
      {"phase", "phase at t = 0 (radians)", -std::numeric_limits<double>::infinity(), false, 0.0, {0, 0},
       &HarmonicForcing::phase},
  }};

  /// From named values (get(name) returns the value or nullopt); phase defaults to 0.
  template <class Get>
  static HarmonicForcing from(Get&& get) {
    HarmonicForcing h;
    h.amplitude = T(get("amplitude").value_or(0.0));
    h.omega = T(get("omega").value_or(0.0));
    h.phase = T(get("phase").value_or(0.0));
    return h;
  }

  /// The force at time t.
  T force(double t) const {
    using std::cos;
    return amplitude * cos(omega * t + phase);
  }
  /// ∂force/∂t.
  T force_dt(double t) const {
    using std::sin;
    return -amplitude * omega * sin(omega * t + phase);
  }
  /// The shift of the time origin that gives the force the phase `other` instead of phase:
  /// force with phase `other` at t = force at t + (other − phase)/omega.
  T time_shift_to(const T& other) const { return (other - phase) / omega; }
  /// The fastest rate the force varies at (step-size rules): |omega|.
  T rate() const {
    using std::abs;
    return abs(omega);
  }
};

/// Adds the force at t0 + i·dt to out[i], i = 0 … n − 1.
inline void add_harmonic_forcing_record_force(const HarmonicForcing<double>& h, double t0, double dt, std::size_t n,
                                              double* out) {
  for (std::size_t i = 0; i < n; ++i) out[i] += h.force(t0 + static_cast<double>(i) * dt);
}

}  // namespace vehs::effects
