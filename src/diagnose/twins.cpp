#include "twins.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <tuple>

#include "vehs/core/error.hpp"
#include "vehs/core/record_phases.hpp"
#include "vehs/diagnose/lens.hpp"
#include "vehs/likelihood/signals.hpp"

namespace vehs::diagnose::detail {

namespace {
std::uint64_t splitmix(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
}  // namespace

void initial_states(const Dataset& data, int smoothing, std::vector<double>& x0, std::vector<double>& y0) {
  x0.clear();
  y0.clear();
  for (const auto& r : data.records) {
    const double* x = data.x_of(r);
    const double dt = r.dt;
    if (smoothing <= 1 || r.size < static_cast<std::size_t>(2 * smoothing + 1)) {
      x0.push_back(x[0]);
      y0.push_back(r.size >= 3 ? (-3.0 * x[0] + 4.0 * x[1] - x[2]) / (2.0 * dt)
                               : (r.size >= 2 ? (x[1] - x[0]) / dt : 0.0));
      continue;
    }
    // least-squares quadratic x ≈ c0 + c1 τ + c2 τ² over τ = 0 .. 2w (in samples)
    const int m = 2 * smoothing + 1;
    double S[5] = {0, 0, 0, 0, 0}, T[3] = {0, 0, 0};
    for (int i = 0; i < m; ++i) {
      const double t = i, t2 = t * t;
      S[0] += 1, S[1] += t, S[2] += t2, S[3] += t2 * t, S[4] += t2 * t2;
      T[0] += x[i], T[1] += t * x[i], T[2] += t2 * x[i];
    }
    // solve the 3x3 normal equations by Cramer's rule
    const double a11 = S[0], a12 = S[1], a13 = S[2], a22 = S[2], a23 = S[3], a33 = S[4];
    const double det = a11 * (a22 * a33 - a23 * a23) - a12 * (a12 * a33 - a23 * a13) + a13 * (a12 * a23 - a22 * a13);
    const double c0 = (T[0] * (a22 * a33 - a23 * a23) - a12 * (T[1] * a33 - a23 * T[2]) + a13 * (T[1] * a23 - a22 * T[2])) / det;
    const double c1 = (a11 * (T[1] * a33 - a23 * T[2]) - T[0] * (a12 * a33 - a23 * a13) + a13 * (a12 * T[2] - T[1] * a13)) / det;
    x0.push_back(c0);
    y0.push_back(c1 / dt);
  }
}

int continuous_twin_substeps(const Model& model, double dt, double x_lo, double x_hi, double v_lo, double v_hi) {
  const CompiledTerms drift(model.drift);
  const ExplicitForces forces(model);
  double rho = 0.0;  // largest root modulus of λ² − bλ − a (a = ∂b2/∂x, b = ∂b2/∂y) over the box
  const int nx = 41, nv = 11;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < nv; ++j) {
      const double x = x_lo + (x_hi - x_lo) * i / (nx - 1), v = v_lo + (v_hi - v_lo) * j / (nv - 1);
      const double a = std::abs(drift.d_dx(x, v)) + (forces.has_stop ? std::abs(forces.stop.stiffness()) : 0.0);
      const double b = std::abs(drift.d_dy(x, v, 0.0));
      rho = std::max(rho, 0.5 * (b + std::sqrt(b * b + 4.0 * a)));
    }
  if (forces.harmonic) rho = std::max(rho, forces.forcing.rate());
  for (const auto& e : model.effects) {  // the hidden states' own rates
    if (e.id == EffectId::ElectromechanicalCoupling)
      rho = std::max({rho, std::abs(e.param("lambda")), std::sqrt(std::abs(e.param("coupling")))});
    if (e.id == EffectId::ColoredNoise && e.param("tau") > 0.0) rho = std::max(rho, 1.0 / e.param("tau"));
  }
  const double n = std::ceil(rho * dt / 0.02);
  return std::isfinite(n) ? static_cast<int>(std::clamp(n, 10.0, 2000.0)) : 10;
}

double twin_divergence_bound(const Dataset& data) {
  double extent = 0.0;
  for (const auto& r : data.records) {
    const double* x = data.x_of(r);
    for (std::size_t i = 0; i < r.size; ++i) {
      extent = std::max(extent, std::abs(x[i]));
      if (i > 0 && r.dt > 0.0) extent = std::max(extent, std::abs(x[i] - x[i - 1]) / r.dt);
    }
  }
  const double bound = kTwinDivergenceExtents * extent;
  if (!(bound > 0.0)) return kTwinDivergenceExtents;  // data all zero: the simulator's default
  return std::min(bound, std::numeric_limits<double>::max());
}

TwinSimulator::TwinSimulator(const Model& model, const Dataset& data, const TwinSettings& settings)
    : model_(model), data_(data), settings_(settings), divergence_bound_(twin_divergence_bound(data)) {
  initial_states(data, settings.smoothing, x0_, y0_);
  harmonic_ = model.find_effect(EffectId::HarmonicForcing) != nullptr;
  if (model.uses_drive() && data.has_u() && settings.input != InputInterpolation::ZeroOrderHold)
    fine_ = std::max(settings.substeps, 1);
  // harmonic forcing in the records' own time: t0, or the time origin of a record's own phase
  const std::vector<double> origin = forcing_time_origins(model, data, "diagnose");
  std::map<std::tuple<std::size_t, double, std::size_t>, std::size_t> index;
  for (std::size_t r = 0; r < data.records.size(); ++r) {
    const auto& rec = data.records[r];
    // records of one length (and start time, with harmonic forcing) are simulated together;
    // with an interpolated input one at a time (memory: samples × substeps)
    const std::tuple<std::size_t, double, std::size_t> key{rec.size, harmonic_ ? origin[r] : 0.0, fine_ > 1 ? r : 0};
    auto it = index.find(key);
    if (it == index.end()) {
      it = index.emplace(key, groups_.size()).first;
      groups_.push_back(Group{{}, std::get<1>(key), rec.size});
    }
    groups_[it->second].records.push_back(r);
  }
}

std::vector<double> TwinSimulator::drive_of(std::size_t r, std::size_t samples) const {
  const double* u = data_.u_of(data_.records[r]);
  std::vector<double> held(u, u + samples);
  return fine_ > 1 ? likelihood::refine_input(held, fine_, settings_.input) : held;
}

void TwinSimulator::simulate(int rep, Dataset& out) {
  const double dt = data_.records.front().dt;
  const bool one_group = groups_.size() == 1 && fine_ == 1;
  if (!one_group) {
    out.records = data_.records;
    out.x.resize(data_.x.size());
    // the input the twins were driven by, at the data's instants (refits of the twins need it:
    // an interpolated input simulates every record on its own, and the twins had no u, so the
    // parameter-uncertainty refits failed with "the data have no drive column u")
    out.u = model_.uses_drive() ? data_.u : Column{};
    out.y.clear();
  }
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    const Group& G = groups_[g];
    sim::SimulationOptions o;
    o.dt = dt / fine_;
    o.substeps = fine_ > 1 ? 1 : settings_.substeps;
    o.samples = (G.samples - 1) * static_cast<std::size_t>(fine_) + 1;
    o.records = static_cast<int>(G.records.size());
    o.scheme = settings_.scheme;
    o.seed = splitmix(splitmix(settings_.seed) ^ (static_cast<std::uint64_t>(rep) << 32) ^ g);
    o.x0.uniform = false;
    o.sensor_noise = settings_.sensor_noise;
    o.record_y = false;
    o.allow_unconfined = true;  // a divergent model is reported as such by the simulator
    o.divergence_bound = divergence_bound_;
    o.memory_limit = settings_.memory_limit;
    const bool driven = model_.uses_drive() && data_.has_u();
    Model m = model_;
    if (harmonic_ && G.t0 != 0.0)
      for (auto& e : m.effects)
        if (e.id == EffectId::HarmonicForcing) e.params["phase"] += e.param("omega") * G.t0;
    Dataset& target = one_group ? out : scratch_;
    try {
      // the drives (samples × substeps each when refined) only once the simulator's memory
      // limit allows them and the records they drive
      if (driven) sim::check_memory(o, true, static_cast<double>(o.records) * static_cast<double>(o.samples));
      for (std::size_t r : G.records) {
        o.x0.values.push_back(x0_[r]);
        o.x0.y_values.push_back(y0_[r]);
        if (driven) o.drive_per_record.push_back(drive_of(r, G.samples));
      }
      sim::simulate(m, o, target);
    } catch (const Error& e) {
      throw Error(std::string("simulating the model's twins of the data failed: ") + e.what());
    }
    if (one_group) {
      // keep the data's record metadata (source, id, t0) so that errors name the data
      for (std::size_t i = 0; i < G.records.size(); ++i) {
        const auto& d = data_.records[G.records[i]];
        Record& t = target.records[i];
        t.source = "twin of " + d.source;
        t.id = d.id;
        t.t0 = d.t0;
      }
      // records are in the data's order when there is one group
      continue;
    }
    for (std::size_t i = 0; i < G.records.size(); ++i) {
      const Record& d = data_.records[G.records[i]];
      const Record& t = scratch_.records[i];
      for (std::size_t k = 0; k < d.size; ++k)  // every fine_-th sample: the data's instants
        out.x[d.offset + k] = scratch_.x[t.offset + k * static_cast<std::size_t>(fine_)];
      out.records[G.records[i]].source = "twin of " + d.source;
    }
  }
  if (settings_.quantisation_step > 0.0) round_to_grid(out);
}

void TwinSimulator::round_to_grid(Dataset& out) const {
  const double q = settings_.quantisation_step;
  for (std::size_t r = 0; r < data_.records.size(); ++r) {
    const double origin = data_.x_of(data_.records[r])[0];
    const Record& t = out.records[r];
    for (std::size_t k = 0; k < t.size; ++k) {
      double& x = out.x[t.offset + k];
      x = origin + q * std::round((x - origin) / q);
    }
  }
}

}  // namespace vehs::diagnose::detail
