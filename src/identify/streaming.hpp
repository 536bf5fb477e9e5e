#pragma once
// Internal: identify's streaming passes over the records. A pass cuts every record into work
// items (spans: a fold's rows, at most kMaxSpanRows), runs them in parallel with one
// accumulator each, and folds the accumulators in span order, so results do not depend on the
// thread count. The Context holds what a pass reads: the data, the dictionaries, the
// kinematics and the corrections of the acceleration target.
#include <algorithm>
#include <cstddef>
#include <exception>
#include <mutex>
#include <vector>

#include <Eigen/Dense>

#include "fourth_derivative.hpp"
#include "kinematics.hpp"
#include "vehs/core/dataset.hpp"
#include "vehs/core/detail/progress_counter.hpp"
#include "vehs/identify/dictionary.hpp"
#include "vehs/identify/gram.hpp"

namespace vehs::identify::detail {

inline constexpr std::size_t kMaxSpanRows = 1u << 16;  // rows per work item
inline constexpr std::size_t kBatchSpans = 32;         // work items reduced together (fixed: determinism)
inline constexpr Eigen::Index kB = kBlockRows;

struct DriftModel;

struct Span {
  std::size_t record = 0;
  std::size_t begin = 0, end = 0;  // rows
  int fold = 0;
};

/// Cuts every record into its folds (contiguous time blocks) and the folds into pieces of at
/// most kMaxSpanRows rows. `row_limit` > 0 keeps only the first rows of each record (pilot).
inline std::vector<Span> make_spans(const Dataset& d, const Kinematics& kin, int folds,
                             std::size_t row_limit) {
  std::vector<Span> spans;
  for (std::size_t r = 0; r < d.records.size(); ++r) {
    std::size_t R = kin.rows(d.records[r].size);
    if (row_limit > 0) R = std::min(R, row_limit);
    for (int f = 0; f < folds; ++f) {
      const std::size_t b = R * static_cast<std::size_t>(f) / static_cast<std::size_t>(folds);
      const std::size_t e = R * static_cast<std::size_t>(f + 1) / static_cast<std::size_t>(folds);
      if (e <= b) continue;
      const std::size_t pieces = (e - b + kMaxSpanRows - 1) / kMaxSpanRows;
      for (std::size_t p = 0; p < pieces; ++p)
        spans.push_back({r, b + (e - b) * p / pieces, b + (e - b) * (p + 1) / pieces, f});
    }
  }
  return spans;
}

/// Runs `work(span, acc)` over all spans in parallel and folds the accumulators into the
/// result with `reduce(span, acc)` in span order, so results do not depend on the thread count.
template <class Acc, class Make, class Work, class Reduce>
void run_spans(const std::vector<Span>& spans, Make make, Work work, Reduce reduce,
               vehs::detail::ProgressCounter* progress) {
  for (std::size_t b0 = 0; b0 < spans.size(); b0 += kBatchSpans) {
    const std::size_t nb = std::min(kBatchSpans, spans.size() - b0);
    std::vector<Acc> acc;
    acc.reserve(nb);
    for (std::size_t i = 0; i < nb; ++i) acc.push_back(make());
    std::exception_ptr failure;
    std::mutex failure_mutex;
#pragma omp parallel for schedule(dynamic, 1)
    for (long i = 0; i < static_cast<long>(nb); ++i) {
      try {
        work(spans[b0 + static_cast<std::size_t>(i)], acc[static_cast<std::size_t>(i)]);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
      }
      if (progress) progress->advance(1);
    }
    if (failure) std::rethrow_exception(failure);
    for (std::size_t i = 0; i < nb; ++i) reduce(spans[b0 + i], acc[i]);
  }
}

/// C += Aᵀ B on the first m rows of column-major blocks (lower: only i ≥ j, A == B).
inline void add_AtB(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, int m, int na, int nb, Eigen::MatrixXd& C,
                    bool lower = false) {
  detail::add_AtB(A.data(), A.outerStride(), B.data(), B.outerStride(), m, na, nb, C.data(),
                   C.outerStride(), lower);
}

struct Context {
  const Dataset& data;
  const Dictionary& phi;  // drift library
  const Dictionary& psi;  // diffusion library
  Kinematics kin;
  const FourthDerivative* jerk = nullptr;  // O(h²) correction of the target (central kinematics)
  const double* known = nullptr;  // known force per sample, aligned with data.x (or null)
  const DriftModel* lens = nullptr;  // the passes leave out the rows too stiff for the lens under it (lens_mask.hpp)

  /// Rows [j0, j0 + m) of a record, the acceleration target corrected by −(h²/12)·x⁗ and
  /// by the known force.
  void load(const double* x, const double* u, std::size_t j0, int m, RowBlock& b) const {
    kin.load(x, u, j0, m, b);
    if (jerk)
      for (int c = 0; c < m; ++c) b.a[c] -= (*jerk)(b.x[c], b.v[c]);
    if (known) {
      const double* f = known + (x - data.x.data()) + kin.sample(j0);
      for (int c = 0; c < m; ++c) b.a[c] -= f[c];
    }
  }
};

}  // namespace vehs::identify::detail
