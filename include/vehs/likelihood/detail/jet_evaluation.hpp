#pragma once
// Value and derivatives of the log-likelihood by forward-mode automatic differentiation
// (ceres::Jet with N slots): each block seeds the shared parameters in slots 0 … S−1 and its
// record's phase (per-record phases) in slot S, runs the same filter as the double evaluation,
// and maps the slots back to θ. Optionally accumulates the Fisher information of the
// innovations, Σ_k ∂e_k∂e_kᵀ/S_k + ½ ∂S_k∂S_kᵀ/S_k², and the score sums of contiguous batches.
// Included by src/likelihood/jets_*.cpp only (each instantiates a few N).
#include <map>

#include <ceres/jet.h>

#include "vehs/likelihood/detail/evaluator.hpp"

namespace vehs::likelihood::detail {

template <int N>
bool evaluate_jets(const Evaluator& ev, const double* theta, Derivatives& out, bool fisher,
                   bool batches, EvaluationFailure* failure) {
  using J = ceres::Jet<double, N>;
  const Parameterization& p = ev.parameterization();
  const std::vector<Block>& blocks = ev.blocks();
  const Dataset& data = ev.data();
  const int S = int(p.shared()), slots = ev.slots();
  const std::size_t P = p.size();

  // batches: contiguous pieces of every record (one per record when batch_samples == 0)
  std::vector<std::size_t> batch_base(data.records.size() + 1, 0);
  for (std::size_t r = 0; r < data.records.size(); ++r) {
    const std::size_t n = data.records[r].size, b = ev.batch_samples;
    batch_base[r + 1] = batch_base[r] + (b == 0 ? 1 : (n + b - 1) / b);
  }

  struct Part {
    double ll = 0.0;
    Eigen::Matrix<double, N, 1> grad = Eigen::Matrix<double, N, 1>::Zero();
    Eigen::Matrix<double, N, N> info = Eigen::Matrix<double, N, N>::Zero();
    std::map<std::size_t, Eigen::Matrix<double, N, 1>> batch;
  };
  std::vector<Part> parts(blocks.size());
  std::vector<EvaluationFailure> fails(blocks.size());
  const long nb = long(blocks.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(ev.threads())
  for (long bi = 0; bi < nb; ++bi) {
    const Block& b = blocks[std::size_t(bi)];
    Part& part = parts[std::size_t(bi)];
    std::vector<J> th(static_cast<std::size_t>(S));
    for (int i = 0; i < S; ++i) th[std::size_t(i)] = J(theta[i], i);
    J ph;
    if (p.local_phase()) ph = J(theta[p.phase_index(b.record)], S);
    Coefficients<J> c;
    p.coefficients(th.data(), &ph, c);
    auto sink = [&](std::size_t k, const J& e, const J& Sk, const J& ell, const auto&) {
      if (fisher) {
        const double inv = 1.0 / Sk.a;
        part.info.noalias() += (inv * e.v) * e.v.transpose();
        part.info.noalias() += (0.5 * inv * inv * Sk.v) * Sk.v.transpose();
      }
      if (batches) {
        const std::size_t pos = b.first + k;
        const std::size_t id = batch_base[b.record] + (ev.batch_samples == 0 ? 0 : pos / ev.batch_samples);
        auto it = part.batch.find(id);
        if (it == part.batch.end()) it = part.batch.emplace(id, Eigen::Matrix<double, N, 1>::Zero()).first;
        it->second += ell.v;
      }
    };
    FilterFailure ff;
    const Structure& st = p.structure();
    const J ll = st.dim() == 2 ? filter_block<J, 2>(st, c, b.data, ev.settings(), sink, ff)
                               : filter_block<J, 4>(st, c, b.data, ev.settings(), sink, ff);
    if (ff.failed) {
      fails[std::size_t(bi)] = {true, b.record, b.first + ff.sample, ff.what};
      continue;
    }
    part.ll = ll.a;
    part.grad = ll.v;
  }
  for (const auto& f : fails)
    if (f.failed) {
      if (failure) *failure = f;
      return false;
    }
  out.log_likelihood = 0.0;
  out.gradient = Eigen::VectorXd::Zero(Eigen::Index(P));
  if (fisher) out.fisher = Eigen::MatrixXd::Zero(Eigen::Index(P), Eigen::Index(P));
  if (batches) out.batch_scores = Eigen::MatrixXd::Zero(Eigen::Index(batch_base.back()), Eigen::Index(P));
  for (std::size_t bi = 0; bi < blocks.size(); ++bi) {
    const Part& part = parts[bi];
    const std::size_t rec = blocks[bi].record;
    auto global = [&](int slot) {
      return Eigen::Index(slot < S ? std::size_t(slot) : p.phase_index(rec));
    };
    out.log_likelihood += part.ll;
    for (int i = 0; i < slots; ++i) out.gradient[global(i)] += part.grad[i];
    if (fisher)
      for (int i = 0; i < slots; ++i)
        for (int j = 0; j < slots; ++j) out.fisher(global(i), global(j)) += part.info(i, j);
    if (batches)
      for (const auto& [id, s] : part.batch)
        for (int i = 0; i < slots; ++i) out.batch_scores(Eigen::Index(id), global(i)) += s[i];
  }
  if (!std::isfinite(out.log_likelihood) || !out.gradient.allFinite()) {
    if (failure) *failure = {true, 0, 0, "the log-likelihood or its gradient is not finite"};
    return false;
  }
  return true;
}

}  // namespace vehs::likelihood::detail
