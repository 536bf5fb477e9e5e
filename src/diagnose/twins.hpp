#pragma once
// Twins (private): records simulated from the model, one per data record and replicate, with the
// record's duration, sampling interval, initial state, drive and measurement process.
#include <cstdint>
#include <vector>

#include "vehs/core/fit_info.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/dataset.hpp"
#include "vehs/sim/simulate.hpp"

namespace vehs::diagnose::detail {

struct TwinSettings {
  sim::Scheme scheme = sim::Scheme::Rk4Euler;
  int substeps = 1;
  double sensor_noise = 0.0;
  /// > 0: the data's values lie on a grid of this step (vehs/core/quantisation.hpp) and the
  /// twins are rounded to it, each record from its data record's first value, after their white
  /// sensor noise (the part of the lens's noise beyond the rounding's q²/12): a sensor's
  /// rounding is a staircase, white noise only between samples far enough apart, and twins with
  /// white noise in its place made the true model of 12-bit counts at 20 kHz inadequate
  /// (electromechanical_coupling claimed at z 45).
  double quantisation_step = 0.0;
  std::uint64_t seed = 1;
  int smoothing = 1;  ///< half-width (samples) of the initial-state fit; > 1 with sensor noise
  /// How the recorded input is applied between samples (the model fit's `input`). Other than
  /// held, the twins step at Δt/substeps with the interpolated input at each step's midpoint
  /// (likelihood::refine_input, as simulate-vehs does), one record at a time, and keep every
  /// substeps-th sample: memory of a record's samples × substeps.
  InputInterpolation input = InputInterpolation::ZeroOrderHold;
  /// The simulator's memory limit for one simulation of the twins (bytes; 0: its default), checked
  /// before the drives are refined.
  double memory_limit = 0.0;
};

/// Initial displacement and velocity of every record: x[0] and the second-order one-sided
/// difference (−3x0 + 4x1 − x2)/(2Δt) for clean data; with smoothing w > 1 a least-squares
/// quadratic over the first 2w + 1 samples (sensor noise).
void initial_states(const Dataset& data, int smoothing, std::vector<double>& x0, std::vector<double>& y0);

/// Internal steps per sampling interval for twins of a continuous-time model: at least 10, and
/// enough that ρ·h ≤ 0.02 with ρ the model's fastest linearised rate over the box
/// [x_lo, x_hi] × [v_lo, v_hi] (the data's range): at coarse sampling (ω·Δt ≈ 1) a fixed 10
/// substeps left a discretisation bias the tests saw (issue 13; a driven Duffing at 10 samples
/// per period was inadequate on its own data in 5 of 10 seeds with 10 substeps, 10 of 10 with 40).
int continuous_twin_substeps(const Model& model, double dt, double x_lo, double x_hi, double v_lo, double v_hi);

/// |x| or |y| beyond which a twin counts as diverged: kTwinDivergenceExtents times the data's own
/// extent (the largest |x| of the samples and |Δx|/Δt between them), so that the bound is in the
/// data's units (the simulator's default of 1e8 stopped data in physical units x1e12 at their
/// first sample, a bound no key raised).
constexpr double kTwinDivergenceExtents = 1e8;
double twin_divergence_bound(const Dataset& data);

class TwinSimulator {
 public:
  TwinSimulator(const Model& model, const Dataset& data, const TwinSettings& settings);
  /// Simulates replicate `rep` into `out` (records in the data's order, same sizes and t0).
  void simulate(int rep, Dataset& out);
  /// The twins' x rounded to the data's grid (settings.quantisation_step).
  void round_to_grid(Dataset& out) const;

 private:
  struct Group {
    std::vector<std::size_t> records;
    double t0 = 0.0;
    std::size_t samples = 0;
  };
  /// The recorded input of record r as the twins apply it (refined when fine_ > 1).
  std::vector<double> drive_of(std::size_t r, std::size_t samples) const;
  const Model& model_;
  const Dataset& data_;
  TwinSettings settings_;
  std::vector<double> x0_, y0_;
  std::vector<Group> groups_;
  bool harmonic_ = false;
  double divergence_bound_ = 1e8;
  int fine_ = 1;  ///< > 1: an interpolated input, simulated on steps of Δt/fine_ (one per step)
  Dataset scratch_;
};

}  // namespace vehs::diagnose::detail
