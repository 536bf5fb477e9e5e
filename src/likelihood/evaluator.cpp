#include "vehs/likelihood/detail/evaluator.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/data_scales.hpp"

namespace vehs::likelihood::detail {

namespace {

void check_data(const Structure& st, const Dataset& data, const std::string& where) {
  if (data.has_u() && data.u.size() != data.x.size())
    throw Error(where + ": the input has " + std::to_string(data.u.size()) + " samples for " +
                std::to_string(data.x.size()) + " samples of x");
  if (st.drive && !data.has_u())
    throw Error(where + ": the model has a drive term 'u' but the data have no input column");
  RecordChecks checks;  // the one record validation: at least 2 samples, finite x and u
  checks.positive_dt = false;
  try {
    check_records(data, checks);
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
}

}  // namespace

int automatic_substeps(const Structure& st, const Coefficients<double>& c, const Dataset& data) {
  // the whole range of x in the data: the stiffest drift (x⁹ of a penta-stable potential) sits at
  // the rarest extremes, and RK4 steps sized from the 0.5–99.5 % quantiles left the moment
  // equations' stability region there (the filter "left the model's domain" on the baseline in
  // 4 of 10 seeds of the velocity_dependent_noise study, bench/results/diagnose_calibration_log.md)
  const auto [lo_it, hi_it] = std::minmax_element(data.x.begin(), data.x.end());
  const double xmin = *lo_it, xmax = *hi_it;
  double vy = 0.0;
  for (const auto& r : data.records) {
    const double* x = data.x_of(r);
    for (std::size_t k = 0; k + 1 < r.size; ++k) {
      const double d = (x[k + 1] - x[k]) / r.dt;
      vy = std::max(vy, d * d);
    }
  }
  const double ymax = std::sqrt(vy);
  const double dt = data.records.front().dt;
  double rho = 0.0;
  const int nx = 41, ny = 11;
  // a user's term is read at the grid's resolution: a jump is a finite rise over a cell, as
  // sign(y)'s is none (the filter averages both over the state's spread)
  const double hx = (xmax - xmin) / (nx - 1), hy = 2.0 * ymax / (ny - 1);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const double x = xmin + (xmax - xmin) * i / (nx - 1);
      const double y = -ymax + 2.0 * ymax * j / (ny - 1);
      double a = 0.0, b = 0.0;
      for (std::size_t t = 0; t < st.drift.size(); ++t) {
        a += c.drift[t] * st.drift[t].slope_dx(x, y, hx);
        b += c.drift[t] * st.drift[t].slope_dy(x, y, hy);
      }
      if (st.impact) a -= std::abs(c.stop.stiffness());
      const double r = 0.5 * (std::abs(b) + std::sqrt(b * b + 4.0 * std::abs(a)));
      rho = std::max(rho, r);
    }
  if (st.harmonic) rho = std::max(rho, c.forcing.rate());
  if (st.electro) rho = std::max({rho, std::abs(c.lambda), std::sqrt(std::abs(c.coupling))});
  if (st.colored && c.tau > 0.0) rho = std::max(rho, 1.0 / c.tau);
  const double n = std::ceil(rho * dt / 0.4);
  return int(std::clamp(std::isfinite(n) ? n : 1000.0, 2.0, 1000.0));
}

Evaluator::Evaluator(const Parameterization& p, const Dataset& data, const FilterOptions& options,
                     const std::string& where)
    : p_(p), data_(data), where_(where) {
  if (const std::string why = options.invalid_reason(); !why.empty()) throw Error(where + ": " + why);
  check_data(p.structure(), data, where);
  double dt = 0.0;
  try {
    dt = data.common_dt();
  } catch (const Error& e) {
    throw Error(where + ": sampling mismatch: " + e.what());
  }
  if (!(dt > 0.0)) throw Error(where + ": the sampling interval must be > 0");
  if (p.local_phase() && p.records() != data.records.size())
    throw Error(where + ": the model has phases for " + std::to_string(p.records()) +
                " records but the data have " + std::to_string(data.records.size()));
  // data-based priors of the hidden states at a block's first sample
  const double y_var = std::max(2.0 * mean_squared_rate(data), 1e-300);
  const double x_var = std::max(2.0 * x_variance(data), 1e-300);
  const std::size_t bl = std::max<std::size_t>(options.block_samples, 2);
  for (std::size_t ri = 0; ri < data.records.size(); ++ri) {
    const Record& r = data.records[ri];
    const std::size_t pieces = std::max<std::size_t>(1, (r.size + bl / 2) / bl);
    for (std::size_t b = 0; b < pieces; ++b) {
      const std::size_t first = r.size * b / pieces, last = r.size * (b + 1) / pieces;
      if (last - first < 2) continue;
      Block blk;
      blk.record = ri;
      blk.first = first;
      blk.data.x = data.x_of(r) + first;
      blk.data.record_u = p.structure().drive ? data.u_of(r) : nullptr;
      blk.data.record_n = r.size;
      blk.data.first = first;
      blk.data.n = last - first;
      blk.data.t0 = r.t0 + double(first) * dt;
      blk.data.dt = dt;
      blk.data.y_prior_var = y_var;
      blk.data.v_prior_var = x_var;
      observations_ += blk.data.n - 1;
      blocks_.push_back(blk);
    }
  }
  Coefficients<double> c0;
  p.coefficients(p.initial().data(), p.local_phase() ? &p.initial()[p.phase_index(0)] : nullptr, c0);
  settings_.substeps =
      options.substeps > 0 ? options.substeps : automatic_substeps(p.structure(), c0, data);
  settings_.input = options.input;
  threads_ = options.threads > 0 ? options.threads : omp_get_max_threads();
}

std::string Evaluator::message(const EvaluationFailure& f) const {
  const Record& r = data_.records[f.record];
  return where_ + ": the filter diverged in " + r.source + " record " + std::to_string(r.id) +
         " at sample " + std::to_string(f.sample) + " (line " +
         std::to_string(r.first_line + f.sample) + "): " + f.what;
}

namespace {

/// Runs `fn(block index)` over all blocks in parallel; fn returns false on failure.
template <class Fn>
bool for_blocks(const std::vector<Block>& blocks, int threads, std::vector<EvaluationFailure>& fails,
                Fn fn) {
  fails.assign(blocks.size(), {});
  const long n = long(blocks.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long i = 0; i < n; ++i) fn(std::size_t(i), fails[std::size_t(i)]);
  for (const auto& f : fails)
    if (f.failed) return false;
  return true;
}

template <class T, class Sink>
T run_block(const Structure& st, const Coefficients<T>& c, const Block& b, const FilterSettings& fs,
            Sink&& sink, EvaluationFailure& fail) {
  FilterFailure ff;
  T ll = st.dim() == 2 ? filter_block<T, 2>(st, c, b.data, fs, sink, ff)
                       : filter_block<T, 4>(st, c, b.data, fs, sink, ff);
  if (ff.failed) fail = {true, b.record, b.first + ff.sample, ff.what};
  return ll;
}

bool first_failure(const std::vector<EvaluationFailure>& fails, EvaluationFailure* out) {
  for (const auto& f : fails)
    if (f.failed) {
      if (out) *out = f;
      return false;
    }
  return true;
}

}  // namespace

bool Evaluator::record_values(const double* theta, std::vector<double>& per_record,
                              EvaluationFailure* failure) const {
  std::vector<double> part(blocks_.size(), 0.0);
  std::vector<EvaluationFailure> fails;
  for_blocks(blocks_, threads_, fails, [&](std::size_t i, EvaluationFailure& f) {
    const Block& b = blocks_[i];
    Coefficients<double> c;
    const double* ph = p_.local_phase() ? theta + p_.phase_index(b.record) : nullptr;
    p_.coefficients(theta, ph, c);
    part[i] = run_block(p_.structure(), c, b, settings_, NoSink{}, f);
  });
  if (!first_failure(fails, failure)) return false;
  per_record.assign(data_.records.size(), 0.0);
  for (std::size_t i = 0; i < blocks_.size(); ++i) per_record[blocks_[i].record] += part[i];
  return true;
}

bool Evaluator::value(const double* theta, double& ll, EvaluationFailure* failure) const {
  std::vector<double> per_record;
  if (!record_values(theta, per_record, failure)) return false;
  ll = 0.0;
  for (double v : per_record) ll += v;
  if (!std::isfinite(ll)) {
    if (failure) *failure = {true, 0, 0, "the log-likelihood is not finite"};
    return false;
  }
  return true;
}

bool Evaluator::trace(const double* theta, FilterTrace& out, EvaluationFailure* failure) const {
  const std::size_t n = data_.x.size();
  out.predicted_x.assign(n, 0.0);
  out.predicted_var.assign(n, 0.0);
  out.filtered_x.assign(n, 0.0);
  out.filtered_y.assign(n, 0.0);
  std::vector<EvaluationFailure> fails;
  for_blocks(blocks_, threads_, fails, [&](std::size_t i, EvaluationFailure& f) {
    const Block& b = blocks_[i];
    const std::size_t base = data_.records[b.record].offset + b.first;
    Coefficients<double> c;
    const double* ph = p_.local_phase() ? theta + p_.phase_index(b.record) : nullptr;
    p_.coefficients(theta, ph, c);
    out.predicted_x[base] = out.filtered_x[base] = b.data.x[0];
    auto sink = [&](std::size_t k, double e, double S, double, const auto& s) {
      out.predicted_x[base + k] = b.data.x[k] - e;
      out.predicted_var[base + k] = S;
      out.filtered_x[base + k] = s[0];
      out.filtered_y[base + k] = s[1];
    };
    run_block(p_.structure(), c, b, settings_, sink, f);
  });
  return first_failure(fails, failure);
}

bool Evaluator::derivatives(const double* theta, Derivatives& out, bool fisher, bool batches,
                            EvaluationFailure* failure) const {
  const int need = slots();
  for (int n : kJetSizes) {
    if (n < need) continue;
    switch (n) {
      case 4: return evaluate_jets<4>(*this, theta, out, fisher, batches, failure);
      case 6: return evaluate_jets<6>(*this, theta, out, fisher, batches, failure);
      case 8: return evaluate_jets<8>(*this, theta, out, fisher, batches, failure);
      case 10: return evaluate_jets<10>(*this, theta, out, fisher, batches, failure);
      case 12: return evaluate_jets<12>(*this, theta, out, fisher, batches, failure);
      case 16: return evaluate_jets<16>(*this, theta, out, fisher, batches, failure);
      case 24: return evaluate_jets<24>(*this, theta, out, fisher, batches, failure);
      default: return evaluate_jets<32>(*this, theta, out, fisher, batches, failure);
    }
  }
  throw Error(where_ + ": " + std::to_string(need) +
              " parameters per record exceed the 32 of the automatic derivatives; hold some fixed");
}

}  // namespace vehs::likelihood::detail
