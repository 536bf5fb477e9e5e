#pragma once
// The map between an observed model and the vector θ the optimiser moves: which numbers are
// free (the model's non-zero coefficients, its dynamic effects' parameters, the measurement
// noise, per-record phases), on which scale, and how θ (of any scalar type) turns into the
// filter's Coefficients. Shared parameters come first in θ, then one phase per record; a block
// of one record depends on the shared ones and its own phase only (the Jet slot after the
// shared ones).
#include <cmath>
#include <string>
#include <vector>

#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/model_structure.hpp"
#include "vehs/likelihood/observed_model.hpp"
#include "vehs/likelihood/parameters.hpp"

namespace vehs::likelihood::detail {

struct FitChoice {
  bool fit_measurement_noise = true;  ///< false: measurement_sd held at its start value
  bool per_record_phase = false;      ///< harmonic_forcing phase per record
  std::vector<std::string> fixed;     ///< further parameter names held at their start values
  /// Parameter names kept on the natural scale even when strictly positive (score tests at a
  /// null value of 0: impact_stop.k_stop, colored_noise.intensity, …).
  std::vector<std::string> natural_scale;
};

class Parameterization {
 public:
  /// Throws vehs::Error (prefixed with `where`) for a model the filter cannot take, unknown
  /// fixed names, or record phases that do not match `records`.
  Parameterization(const ObservedModel& start, const FitChoice& choice, std::size_t records,
                   const std::string& where);

  const Structure& structure() const { return structure_; }
  const std::vector<ParameterInfo>& parameters() const { return params_; }
  std::size_t size() const { return params_.size(); }
  std::size_t shared() const { return shared_; }
  bool local_phase() const { return local_phase_; }
  /// Index of record r's phase in θ (local_phase() only).
  std::size_t phase_index(std::size_t r) const { return shared_ + r; }
  std::size_t records() const { return records_; }

  /// θ of the start model (internal scale).
  const std::vector<double>& initial() const { return initial_; }
  double natural(std::size_t i, double internal) const {
    return params_[i].log_scale ? std::exp(internal) : internal;
  }
  /// d natural / d internal at `internal`.
  double jacobian(std::size_t i, double internal) const {
    return params_[i].log_scale ? std::exp(internal) : 1.0;
  }
  /// The observed model at θ (internal scale); standard errors are not set.
  ObservedModel model_at(const std::vector<double>& theta) const;
  /// The shared phase (or 0) of a record under the start model, for records without local phase.
  double record_phase(std::size_t r) const {
    return start_phases_.empty() ? base_.forcing.phase : start_phases_[r];
  }

  /// Coefficients for one record: `shared` = θ[0 … shared()), `phase` = the record's phase
  /// (local_phase() only, else ignored).
  template <class T>
  void coefficients(const T* shared, const T* phase, Coefficients<T>& c) const {
    using std::exp;
    c.drift.resize(base_.drift.size());
    for (std::size_t j = 0; j < base_.drift.size(); ++j) c.drift[j] = T(base_.drift[j]);
    c.diffusion.resize(base_.diffusion.size());
    for (std::size_t j = 0; j < base_.diffusion.size(); ++j) c.diffusion[j] = T(base_.diffusion[j]);
    lift(base_.stop, c.stop);
    lift(base_.forcing, c.forcing);
    c.lambda = T(base_.lambda);
    c.coupling = T(base_.coupling);
    c.tau = T(base_.tau);
    c.intensity = T(base_.intensity);
    c.measurement_var = T(base_.measurement_var);
    for (std::size_t i = 0; i < shared_; ++i) {
      const ParameterInfo& p = params_[i];
      const T v = p.log_scale ? T(exp(shared[i])) : shared[i];
      target(p, c) = p.kind == ParameterKind::MeasurementSd ? T(v * v) : v;
    }
    if (local_phase_) c.forcing.phase = *phase;
  }

 private:
  /// An effect's parameters in another scalar type.
  template <class T, template <class> class E>
  static void lift(const E<double>& from, E<T>& to) {
    for (std::size_t i = 0; i < E<T>::params.size(); ++i) to.*E<T>::params[i].member = T(from.*E<double>::params[i].member);
  }
  /// The parameter of an effect named `key` (an internal error when the type has none).
  template <class T, template <class> class E>
  static T& member(E<T>& e, const std::string& key) {
    for (const auto& q : E<T>::params)
      if (q.name == key) return e.*q.member;
    throw Error("likelihood: internal error: no effect parameter '" + key + "'");
  }

  template <class T>
  static T& target(const ParameterInfo& p, Coefficients<T>& c) {
    switch (p.kind) {
      case ParameterKind::Drift: return c.drift[p.index];
      case ParameterKind::Diffusion: return c.diffusion[p.index];
      case ParameterKind::MeasurementSd: return c.measurement_var;
      case ParameterKind::RecordPhase: return c.forcing.phase;
      case ParameterKind::Effect: break;
    }
    const std::string& k = p.effect_param;
    if (p.effect == EffectId::ImpactStop) return member(c.stop, k);
    if (p.effect == EffectId::HarmonicForcing) return member(c.forcing, k);
    if (k == "lambda") return c.lambda;
    if (k == "coupling") return c.coupling;
    if (k == "tau") return c.tau;
    if (k == "intensity") return c.intensity;
    throw Error("likelihood: internal error: no effect parameter '" + k + "'");
  }

  ObservedModel start_;
  Structure structure_;
  Coefficients<double> base_;
  std::vector<ParameterInfo> params_;
  std::vector<double> initial_;
  std::vector<double> start_phases_;
  std::size_t shared_ = 0, records_ = 0;
  bool local_phase_ = false;
};

}  // namespace vehs::likelihood::detail
