#include "vehs/identify/regression.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <iomanip>
#include <sstream>

#include <Eigen/Eigenvalues>

#include "best_subset.hpp"

#include "vehs/conventions.hpp"
#include "vehs/core/error.hpp"

namespace vehs::identify {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Eigen::MatrixXd sub_matrix(const Eigen::MatrixXd& G, const std::vector<int>& s) {
  const auto p = static_cast<Eigen::Index>(s.size());
  Eigen::MatrixXd out(p, p);
  for (Eigen::Index i = 0; i < p; ++i)
    for (Eigen::Index j = 0; j < p; ++j) out(i, j) = G(s[static_cast<std::size_t>(i)], s[static_cast<std::size_t>(j)]);
  return out;
}
}  // namespace

QuadraticStats& QuadraticStats::operator+=(const QuadraticStats& o) {
  if (G.size() == 0) {
    *this = o;
    return *this;
  }
  G += o.G;
  b += o.b;
  c0 += o.c0;
  n += o.n;
  return *this;
}

QuadraticStats& QuadraticStats::operator-=(const QuadraticStats& o) {
  G -= o.G;
  b -= o.b;
  c0 -= o.c0;
  n -= o.n;
  return *this;
}

double QuadraticStats::loss(const std::vector<int>& support, const Eigen::VectorXd& coef) const {
  double l = c0;
  for (std::size_t i = 0; i < support.size(); ++i) {
    const double ci = coef[static_cast<Eigen::Index>(i)];
    l -= 2.0 * ci * b[support[i]];
    for (std::size_t j = 0; j < support.size(); ++j)
      l += ci * G(support[i], support[j]) * coef[static_cast<Eigen::Index>(j)];
  }
  return l;
}

double equilibrated_condition(const Eigen::MatrixXd& G, const std::vector<int>& support,
                              Eigen::VectorXd* weakest) {
  if (support.empty()) return 1.0;
  Eigen::MatrixXd Gs = sub_matrix(G, support);
  Eigen::VectorXd d = Gs.diagonal();
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    if (!(d[i] > 0.0) || !std::isfinite(d[i])) {
      if (weakest) {
        *weakest = Eigen::VectorXd::Zero(d.size());
        (*weakest)[i] = 1.0;
      }
      return kInf;
    }
    d[i] = 1.0 / std::sqrt(d[i]);
  }
  const Eigen::MatrixXd E = d.asDiagonal() * Gs * d.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(E);
  if (es.info() != Eigen::Success) return kInf;
  const double lmin = es.eigenvalues()[0], lmax = es.eigenvalues()[es.eigenvalues().size() - 1];
  if (weakest) *weakest = es.eigenvectors().col(0);
  if (!(lmin > 0.0)) return kInf;
  return lmax / lmin;
}

double require_well_conditioned(const Eigen::MatrixXd& G, const std::vector<int>& support,
                                const std::vector<std::string>& names, const std::string& what) {
  Eigen::VectorXd weakest;
  const double cond = equilibrated_condition(G, support, &weakest);
  if (cond <= conventions::max_gram_condition) return cond;
  // name the terms that make up the (nearly) null direction, largest weights first
  std::vector<std::pair<double, int>> w;
  for (Eigen::Index i = 0; i < weakest.size(); ++i)
    w.push_back({std::abs(weakest[i]), support[static_cast<std::size_t>(i)]});
  std::sort(w.begin(), w.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string terms;
  for (std::size_t i = 0; i < w.size() && i < 4 && w[i].first > 0.05; ++i)
    terms += (terms.empty() ? "" : ", ") + names[static_cast<std::size_t>(w[i].second)];
  std::ostringstream os;
  os << what << " is ill-conditioned on these data (condition number ";
  if (std::isfinite(cond))
    os << std::scientific << std::setprecision(2) << cond;
  else
    os << "infinite";
  os << " > 1e12 after column scaling): nearly collinear terms " << terms
     << "; remove one of them or use a smaller library";
  throw Error(os.str());
}

SupportFit fit_support(const QuadraticStats& s, const std::vector<int>& support) {
  SupportFit f;
  f.support = support;
  const auto p = static_cast<Eigen::Index>(support.size());
  f.coef = Eigen::VectorXd::Zero(p);
  f.t_ratio = Eigen::VectorXd::Zero(p);
  if (p == 0) {
    f.loss = s.c0;
    return f;
  }
  const Eigen::MatrixXd Gs = sub_matrix(s.G, support);
  Eigen::VectorXd bs(p);
  for (Eigen::Index i = 0; i < p; ++i) bs[i] = s.b[support[static_cast<std::size_t>(i)]];
  Eigen::VectorXd d(p);
  bool degenerate = false;
  for (Eigen::Index i = 0; i < p; ++i) {
    if (!(Gs(i, i) > 0.0) || !std::isfinite(Gs(i, i))) {
      degenerate = true;
      d[i] = 1.0;
    } else {
      d[i] = 1.0 / std::sqrt(Gs(i, i));
    }
  }
  if (degenerate) {
    f.condition = kInf;
    f.loss = s.c0;
    return f;
  }
  const Eigen::MatrixXd E = d.asDiagonal() * Gs * d.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(E);
  const double lmin = es.eigenvalues()[0], lmax = es.eigenvalues()[p - 1];
  f.condition = lmin > 0.0 ? lmax / lmin : kInf;
  if (!(lmin > 0.0)) {
    f.loss = s.c0;
    return f;
  }
  // E = V Λ Vᵀ: solve and invert through the eigen-decomposition (p is small)
  const Eigen::MatrixXd Einv =
      es.eigenvectors() * es.eigenvalues().cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
  const Eigen::VectorXd ceq = Einv * (d.asDiagonal() * bs);
  f.coef = d.asDiagonal() * ceq;
  for (Eigen::Index i = 0; i < p; ++i) {
    const double var = Einv(i, i) * d[i] * d[i];
    f.t_ratio[i] = var > 0.0 ? std::abs(f.coef[i]) / std::sqrt(var) : kInf;
  }
  f.loss = s.loss(support, f.coef);
  return f;
}

std::vector<SupportFit> ssr_path(const QuadraticStats& s, const std::vector<int>& initial,
                                 const std::vector<bool>& keep, SsrRule rule) {
  std::vector<SupportFit> path;
  std::vector<int> support = initial;
  while (true) {
    path.push_back(fit_support(s, support));
    const SupportFit& f = path.back();
    int drop = -1;
    double smallest = kInf;
    for (std::size_t i = 0; i < support.size(); ++i) {
      if (keep[static_cast<std::size_t>(support[i])]) continue;
      const double score = rule == SsrRule::TRatio ? f.t_ratio[static_cast<Eigen::Index>(i)]
                                                   : std::abs(f.coef[static_cast<Eigen::Index>(i)]);
      if (score < smallest || drop < 0) {
        smallest = score;
        drop = static_cast<int>(i);
      }
    }
    if (drop < 0) break;
    support.erase(support.begin() + drop);
  }
  return path;
}

std::vector<SupportFit> stlsq_path(const QuadraticStats& s, const std::vector<int>& initial,
                                   const std::vector<bool>& keep, double threshold) {
  std::vector<SupportFit> path;
  std::vector<int> support = initial;
  for (int iter = 0; iter < 100; ++iter) {
    path.push_back(fit_support(s, support));
    const SupportFit& f = path.back();
    std::vector<int> next;
    for (std::size_t i = 0; i < support.size(); ++i)
      if (keep[static_cast<std::size_t>(support[i])] ||
          std::abs(f.coef[static_cast<Eigen::Index>(i)]) >= threshold)
        next.push_back(support[i]);
    if (next == support) break;
    support = next;
  }
  return path;
}

std::string SelectionOptions::invalid_reason() const {
  if (!(stlsq_threshold >= 0.0) || !std::isfinite(stlsq_threshold)) return "stlsq_threshold must be >= 0";
  if (!(variance_factor > 0.0) || !std::isfinite(variance_factor)) return "the BIC's variance factor must be > 0";
  return "";
}

namespace {

/// The BIC's choice improved off the path (best_subset.hpp): the support reached is
/// appended to the path as its last step and chosen.
void take_best_subset(SelectionResult& r, const QuadraticStats& total, const std::vector<int>& initial,
                    const std::vector<bool>& keep, double variance_factor) {
  const SupportFit& chosen = r.path[static_cast<std::size_t>(r.chosen)];
  SupportFit better = bic_best_subset(total, chosen, initial, keep, variance_factor);
  std::vector<int> a = chosen.support, b = better.support;
  std::sort(a.begin(), a.end());
  if (a == b) return;
  const double before = r.bic[static_cast<std::size_t>(r.chosen)];
  const double after = bic(total.n, better.loss, better.support.size(), variance_factor);
  if (!(after < before)) return;
  r.path.push_back(std::move(better));
  r.bic.push_back(after);
  r.cv_loss.push_back(kNaN);
  r.cv_diff.push_back(kNaN);
  r.cv_diff_se.push_back(kNaN);
  r.chosen = static_cast<int>(r.path.size()) - 1;
  r.rule += "; then the lowest BIC over every support with at most one term more (off the path): " +
            std::to_string(before) + " -> " + std::to_string(after) + " (last step)";
}

}  // namespace

SelectionResult select_sparse(const std::vector<QuadraticStats>& folds, const std::vector<int>& initial,
                              const std::vector<bool>& keep, const SelectionOptions& options) {
  require(!folds.empty(), "internal: no fold statistics");
  if (auto why = options.invalid_reason(); !why.empty()) throw Error("selection: " + why);
  const Sparsity sparsity = options.sparsity;
  const SsrRule rule = options.rule;
  const Criterion criterion = options.criterion;
  const double stlsq_threshold = options.stlsq_threshold, variance_factor = options.variance_factor;
  QuadraticStats total;
  for (const auto& f : folds) total += f;
  auto run_path = [&](const QuadraticStats& s) {
    switch (sparsity) {
      case Sparsity::Ssr: return ssr_path(s, initial, keep, rule);
      case Sparsity::Stlsq: return stlsq_path(s, initial, keep, stlsq_threshold);
      case Sparsity::None: break;
    }
    return std::vector<SupportFit>{fit_support(s, initial)};
  };
  SelectionResult r;
  r.path = run_path(total);
  const std::size_t steps = r.path.size();
  const std::size_t F = folds.size();
  r.cv_loss.assign(steps, kNaN);
  r.cv_diff.assign(steps, kNaN);
  r.cv_diff_se.assign(steps, kNaN);
  r.bic.assign(steps, kNaN);
  const double n = total.n;
  for (std::size_t s = 0; s < steps; ++s) r.bic[s] = bic(n, r.path[s].loss, r.path[s].support.size(), variance_factor);
  // held-out contrast per fold and step (for STLSQ only the first and last steps are comparable)
  std::vector<std::vector<double>> fold_loss(steps, std::vector<double>(F, kNaN));
  if (F >= 2) {
    for (std::size_t f = 0; f < F; ++f) {
      QuadraticStats train = total;
      train -= folds[f];
      const auto path = run_path(train);
      if (sparsity == Sparsity::Stlsq) {
        fold_loss[0][f] = folds[f].loss(path.front().support, path.front().coef);
        fold_loss[steps - 1][f] = folds[f].loss(path.back().support, path.back().coef);
      } else {
        for (std::size_t s = 0; s < steps && s < path.size(); ++s)
          fold_loss[s][f] = folds[f].loss(path[s].support, path[s].coef);
      }
    }
    for (std::size_t s = 0; s < steps; ++s) {
      double sum = 0.0;
      for (double v : fold_loss[s]) sum += v;
      r.cv_loss[s] = sum;
    }
    int best = -1;
    for (std::size_t s = 0; s < steps; ++s)
      if (std::isfinite(r.cv_loss[s]) && (best < 0 || r.cv_loss[s] < r.cv_loss[static_cast<std::size_t>(best)]))
        best = static_cast<int>(s);
    r.min_step = std::max(best, 0);
    for (std::size_t s = 0; s < steps; ++s) {
      if (!std::isfinite(r.cv_loss[s])) continue;
      std::vector<double> d(F);
      double mean = 0.0;
      for (std::size_t f = 0; f < F; ++f) {
        d[f] = fold_loss[s][f] - fold_loss[static_cast<std::size_t>(r.min_step)][f];
        mean += d[f] / static_cast<double>(F);
      }
      double var = 0.0;
      for (double v : d) var += (v - mean) * (v - mean);
      var /= static_cast<double>(F - 1);
      r.cv_diff[s] = mean * static_cast<double>(F);
      r.cv_diff_se[s] = std::sqrt(var * static_cast<double>(F));
    }
  }
  if (sparsity == Sparsity::Stlsq) {
    r.chosen = static_cast<int>(steps - 1);
    r.rule = "STLSQ with |coef| threshold " + std::to_string(stlsq_threshold) + ": last iteration";
    return r;
  }
  if (sparsity == Sparsity::None) {
    r.chosen = 0;
    r.rule = "no sparsification: all terms";
    return r;
  }
  const bool cv_possible = F >= 2;
  if (criterion == Criterion::Bic || !cv_possible) {
    int best = 0;
    for (std::size_t s = 0; s < steps; ++s)
      if (std::isfinite(r.bic[s]) && (!std::isfinite(r.bic[static_cast<std::size_t>(best)]) ||
                                      r.bic[s] < r.bic[static_cast<std::size_t>(best)]))
        best = static_cast<int>(s);
    r.chosen = best;
    r.rule = std::string("minimum BIC = n log(L/n)/phi + p log n, phi = ") + std::to_string(variance_factor) +
             " (long-run variance factor of the residuals)" +
             (cv_possible ? "" : " (cross-validation needs at least 2 folds)");
    take_best_subset(r, total, initial, keep, variance_factor);
    return r;
  }
  if (criterion == Criterion::CvMin) {
    r.chosen = r.min_step;
    r.rule = "minimum of the blocked cross-validation contrast";
    return r;
  }
  r.chosen = r.min_step;
  for (std::size_t s = static_cast<std::size_t>(r.min_step); s < steps; ++s)
    if (std::isfinite(r.cv_diff[s]) && r.cv_diff[s] <= r.cv_diff_se[s]) r.chosen = static_cast<int>(s);
  r.rule =
      "sparsest step whose blocked cross-validation contrast exceeds the minimum by at most one "
      "standard error of the paired fold differences";
  return r;
}

std::vector<int> full_support(int n) {
  std::vector<int> v(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) v[static_cast<std::size_t>(i)] = i;
  return v;
}

Eigen::VectorXd full_coefficients(const SupportFit& f, int K) {
  Eigen::VectorXd c = Eigen::VectorXd::Zero(K);
  if (!std::isfinite(f.condition)) return c;
  for (std::size_t i = 0; i < f.support.size(); ++i) c[f.support[i]] = f.coef[static_cast<Eigen::Index>(i)];
  return c;
}

}  // namespace vehs::identify
