#include "vehs/likelihood/detail/bias_correction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vehs/core/error.hpp"
#include "vehs/likelihood/signals.hpp"
#include "vehs/likelihood/detail/evaluator.hpp"
#include "vehs/likelihood/detail/selection.hpp"
#include "vehs/sim/simulate.hpp"

namespace vehs::likelihood::detail {

namespace {

/// Largest number of simulator samples held at once for an interpolated input (one record at a
/// time): 2^24 values of x and of u, 256 MB.
constexpr std::size_t kMaxFineSamples = std::size_t{1} << 24;

/// Record `r` of `data` simulated with its input applied as `input`: held per fine step of
/// dt/keep at each step's midpoint (as simulate-vehs does), every keep-th sample kept.
void simulate_record_fine(const ObservedModel& model, const Dataset& data, std::size_t r, int keep,
                          sim::SimulationOptions so, InputInterpolation input, Dataset& out) {
  const Record& rec = data.records[r];
  const double* x = data.x_of(rec);
  const double dt = rec.dt;
  so.dt = dt / keep;
  so.substeps = 1;
  so.samples = (rec.size - 1) * std::size_t(keep) + 1;
  so.records = 1;
  so.first_record = r;
  so.x0.values = {x[0]};
  so.x0.y_values = {rec.size > 1 ? (x[1] - x[0]) / dt : 0.0};
  so.drive_per_record = {refine_input(std::vector<double>(data.u_of(rec), data.u_of(rec) + rec.size), keep, input)};
  const Dataset s = sim::simulate(model.model, so);
  Record o = rec;
  o.offset = out.x.size();
  const double* xs = s.x_of(s.records[0]);
  for (std::size_t k = 0; k < rec.size; ++k) out.x.push_back(xs[k * std::size_t(keep)]);
  out.u.insert(out.u.end(), data.u_of(rec), data.u_of(rec) + rec.size);
  out.records.push_back(o);
}

}  // namespace

Dataset simulate_like(const ObservedModel& model, const Dataset& data, int substeps, std::uint64_t seed,
                      InputInterpolation input) {
  const double dt = data.common_dt();
  std::size_t n = 0;
  for (const Record& r : data.records) n = std::max(n, r.size);
  sim::SimulationOptions so;
  so.dt = dt;
  so.substeps = substeps;
  so.samples = n;
  so.records = int(data.records.size());
  so.scheme = sim::Scheme::Taylor15;
  so.seed = seed;
  so.sensor_noise = model.measurement_sd;
  so.record_y = false;
  so.x0.uniform = false;
  if (input != InputInterpolation::ZeroOrderHold && data.has_u()) {
    const int keep = int(std::clamp<std::size_t>(kMaxFineSamples / n, 1, std::size_t(substeps)));
    Dataset out;
    for (std::size_t r = 0; r < data.records.size(); ++r) simulate_record_fine(model, data, r, keep, so, input, out);
    return out;
  }
  for (const Record& r : data.records) {
    const double* x = data.x_of(r);
    so.x0.values.push_back(x[0]);
    so.x0.y_values.push_back(r.size > 1 ? (x[1] - x[0]) / dt : 0.0);
    if (data.has_u()) {
      std::vector<double> u(data.u_of(r), data.u_of(r) + r.size);
      u.resize(n, u.back());
      so.drive_per_record.push_back(std::move(u));
    }
  }
  const Dataset s = sim::simulate(model.model, so);
  Dataset out;
  for (std::size_t i = 0; i < data.records.size(); ++i) {
    Record rec = s.records[i];
    rec.size = data.records[i].size;
    rec.offset = out.x.size();
    out.x.insert(out.x.end(), s.x_of(s.records[i]), s.x_of(s.records[i]) + rec.size);
    if (s.has_u()) out.u.insert(out.u.end(), s.u_of(s.records[i]), s.u_of(s.records[i]) + rec.size);
    out.records.push_back(rec);
  }
  return out;
}

void correct_filter_bias(Result& res, const Dataset& data, const RefineOptions& o, const FitChoice& choice) {
  const std::string where = "likelihood bias correction";
  if (choice.per_record_phase) throw Error(where + ": not available with one harmonic_forcing phase per record");
  const Parameterization p(res.model, choice, data.records.size(), where);
  const std::size_t n = p.size();
  if (n != res.parameters.size()) throw Error(where + ": the fitted parameters do not match the model");
  for (std::size_t i = 0; i < n; ++i)
    if (p.parameters()[i].name != res.parameters[i].name)
      throw Error(where + ": the fitted parameters do not match the model");
  const std::vector<double>& theta = p.initial();
  FilterOptions fo = o.filter;
  fo.substeps = res.summary.substeps;
  // the simulator's steps per interval: 8 per filter substep; with an interpolated input 32 (at
  // least 64), as the input is held per step at its midpoint, an O((ω_u·h)²) error the filter does
  // not make (24 steps moved the Silverbox estimate by 18 SE, 96 by 3.9 — the filter's own RK4)
  const bool interpolated = fo.input != InputInterpolation::ZeroOrderHold && data.has_u();
  const int sim_substeps = interpolated ? std::clamp(32 * fo.substeps, 64, 1000) : std::clamp(8 * fo.substeps, 20, 1000);
  const int B = o.bias_correction_datasets;
  Eigen::VectorXd mean_score = Eigen::VectorXd::Zero(Eigen::Index(n));
  for (int b = 0; b < B; ++b) {
    Dataset sim_data;
    try {
      sim_data = simulate_like(res.model, data, sim_substeps, o.bias_correction_seed + std::uint64_t(b),
                               fo.input);
    } catch (const Error& e) {
      throw Error(where + ": cannot simulate the fitted model: " + e.what());
    }
    const Evaluator ev(p, sim_data, fo, where);
    Derivatives d;
    EvaluationFailure f;
    if (!ev.derivatives(theta.data(), d, false, false, &f))
      throw FilterDiverged(ev.message(f) + " (a data set simulated at the estimate)");
    mean_score += d.gradient / double(B);
    if (o.step) o.step();
  }
  // internal-scale covariance from the natural one: C_int = J⁻¹ C J⁻¹
  const Eigen::Index m = Eigen::Index(n);
  Eigen::VectorXd Jinv(m);
  for (std::size_t i = 0; i < n; ++i) Jinv[Eigen::Index(i)] = 1.0 / p.jacobian(i, theta[i]);
  const Eigen::MatrixXd cov_int = Jinv.asDiagonal() * res.covariance * Jinv.asDiagonal();
  const Eigen::VectorXd shift = -(cov_int * mean_score);
  std::vector<double> corrected(theta);
  double max_shift_se = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    corrected[i] += shift[Eigen::Index(i)];
    max_shift_se = std::max(max_shift_se, std::abs(shift[Eigen::Index(i)]) / std::sqrt(cov_int(Eigen::Index(i), Eigen::Index(i))));
    // (a log-scale parameter estimated at 0, e.g. measurement_sd on noise-free data, has no
    // finite internal scale: no correction rather than a NaN in the model file)
    if (!std::isfinite(corrected[i]) || !std::isfinite(p.natural(i, corrected[i])))
    {
      char v[32];
      std::snprintf(v, sizeof v, "%.4g", res.values[i]);
      throw Error(where + ": no finite correction of " + p.parameters()[i].name + " (estimate " + v +
                  " at the edge of its scale)");
    }
  }
  const double inflation = 1.0 + 1.0 / double(B);
  Eigen::VectorXd J(m);
  for (std::size_t i = 0; i < n; ++i) J[Eigen::Index(i)] = p.jacobian(i, corrected[i]);
  res.covariance = inflation * (J.asDiagonal() * cov_int * J.asDiagonal());
  res.model = p.model_at(corrected);
  for (std::size_t i = 0; i < n; ++i) {
    res.values[i] = p.natural(i, corrected[i]);
    res.stderrs[i] = std::sqrt(std::max(res.covariance(Eigen::Index(i), Eigen::Index(i)), 0.0));
  }
  attach_stderrs(res);
  res.summary.bias_correction_datasets = B;
  res.summary.bias_correction_max_se = max_shift_se;
  res.summary.bias_correction_seed = o.bias_correction_seed;
  if (o.log) {
    char line[160];
    std::snprintf(line, sizeof line, "likelihood bias correction: %d simulated data sets, largest shift %.3g SE", B,
                  max_shift_se);
    o.log(line);
  }
}

}  // namespace vehs::likelihood::detail
