#pragma once
// The fitted parameters of an observed model, by name:
//   drift[TERM], diffusion[TERM]         coefficients of b2 and a22 (docs/model-file.md names)
//   EFFECT.PARAM                         dynamic effects' parameters (impact_stop.gap, …)
//   measurement_sd                       the white noise on x
//   phase[r]                             harmonic_forcing phase of record r (per-record phases)
// Strictly positive quantities are optimised on a log scale (diffusion[1] when it starts
// positive, measurement_sd, impact_stop.*, harmonic_forcing.omega,
// electromechanical_coupling.lambda, colored_noise.tau and .intensity); values, standard errors
// and covariances are always reported on the natural scale (delta method).
#include <string>

#include "vehs/core/model.hpp"

namespace vehs::likelihood {

enum class ParameterKind { Drift, Diffusion, Effect, MeasurementSd, RecordPhase };

struct ParameterInfo {
  std::string name;
  ParameterKind kind = ParameterKind::Drift;
  int index = -1;            ///< term index (Drift, Diffusion) or record index (RecordPhase)
  EffectId effect{};         ///< Effect only
  std::string effect_param;  ///< Effect only
  bool log_scale = false;    ///< optimised as log(value)
};

}  // namespace vehs::likelihood
