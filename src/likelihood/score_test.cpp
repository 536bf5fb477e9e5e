#include "vehs/likelihood/score_test.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/evaluator.hpp"

namespace vehs::likelihood {

namespace {

/// Pseudo-inverse of a symmetric positive semi-definite matrix over its identified directions
/// (eigenvalues above 1e-10 of the largest, after scaling to unit diagonal); rank in `rank`.
Eigen::MatrixXd pseudo_inverse(const Eigen::MatrixXd& A, int& rank) {
  const Eigen::Index n = A.rows();
  Eigen::VectorXd d(n);
  for (Eigen::Index i = 0; i < n; ++i) d(i) = A(i, i) > 0.0 ? 1.0 / std::sqrt(A(i, i)) : 0.0;
  const Eigen::MatrixXd S = d.asDiagonal() * (0.5 * (A + A.transpose())) * d.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S);
  const Eigen::VectorXd& ev = es.eigenvalues();
  const double top = n > 0 ? ev.maxCoeff() : 0.0;
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(n);
  rank = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (ev(i) > 1e-10 * top && ev(i) > 0.0) {
      inv(i) = 1.0 / ev(i);
      ++rank;
    }
  const Eigen::MatrixXd Sinv = es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
  return d.asDiagonal() * Sinv * d.asDiagonal();
}

}  // namespace

ScoreTestResult score_test(const ObservedModel& model, const Dataset& data,
                           const std::vector<std::string>& tested, const ScoreTestOptions& options) {
  const std::string where = "score test";
  if (tested.empty()) throw Error(where + ": no parameter to test");
  if (const std::string why = options.filter.invalid_reason(); !why.empty())
    throw Error(where + ": " + why);
  detail::FitChoice choice;
  choice.fit_measurement_noise = options.estimate_measurement_noise && model.measurement_sd > 0.0;
  choice.fixed = options.fixed;
  choice.natural_scale = tested;
  const detail::Parameterization p(model, choice, data.records.size(), where);
  detail::Evaluator ev(p, data, options.filter, where);
  ev.batch_samples = 0;  // one batch per record
  // indices of the tested parameters (ψ) and of the nuisance ones (θ) in the parameter vector
  std::vector<Eigen::Index> psi, theta;
  for (const auto& name : tested) {
    const auto& ps = p.parameters();
    auto it = std::find_if(ps.begin(), ps.end(), [&](const ParameterInfo& q) { return q.name == name; });
    if (it == ps.end()) throw Error(where + ": '" + name + "' is not a free parameter of the model");
    psi.push_back(Eigen::Index(it - ps.begin()));
  }
  for (Eigen::Index i = 0; i < Eigen::Index(p.size()); ++i)
    if (std::find(psi.begin(), psi.end(), i) == psi.end()) theta.push_back(i);

  detail::Derivatives d;
  detail::EvaluationFailure f;
  if (!ev.derivatives(p.initial().data(), d, true, true, &f)) throw Error(ev.message(f));
  const Eigen::MatrixXd& F = d.fisher;
  const Eigen::VectorXd& g = d.gradient;
  const Eigen::Index np = Eigen::Index(psi.size()), nt = Eigen::Index(theta.size());
  Eigen::MatrixXd Fpp(np, np), Fpt(np, nt), Ftt(nt, nt);
  Eigen::VectorXd gp(np), gt(nt);
  for (Eigen::Index a = 0; a < np; ++a) {
    gp(a) = g(psi[std::size_t(a)]);
    for (Eigen::Index b = 0; b < np; ++b) Fpp(a, b) = F(psi[std::size_t(a)], psi[std::size_t(b)]);
    for (Eigen::Index b = 0; b < nt; ++b) Fpt(a, b) = F(psi[std::size_t(a)], theta[std::size_t(b)]);
  }
  for (Eigen::Index a = 0; a < nt; ++a) {
    gt(a) = g(theta[std::size_t(a)]);
    for (Eigen::Index b = 0; b < nt; ++b) Ftt(a, b) = F(theta[std::size_t(a)], theta[std::size_t(b)]);
  }
  int rank_t = 0;
  const Eigen::MatrixXd A = nt > 0 ? Eigen::MatrixXd(Fpt * pseudo_inverse(Ftt, rank_t))
                                   : Eigen::MatrixXd(np, 0);  // F_ψθ F_θθ⁻¹

  ScoreTestResult r;
  r.tested = tested;
  r.efficient_score = nt > 0 ? Eigen::VectorXd(gp - A * gt) : gp;
  r.efficient_information = nt > 0 ? Eigen::MatrixXd(Fpp - A * Fpt.transpose()) : Fpp;
  const Eigen::MatrixXd& B = d.batch_scores;  // records × parameters (internal scale)
  r.record_scores.resize(B.rows(), np);
  for (Eigen::Index k = 0; k < B.rows(); ++k) {
    Eigen::VectorXd bp(np), bt(nt);
    for (Eigen::Index a = 0; a < np; ++a) bp(a) = B(k, psi[std::size_t(a)]);
    for (Eigen::Index a = 0; a < nt; ++a) bt(a) = B(k, theta[std::size_t(a)]);
    r.record_scores.row(k) = (nt > 0 ? Eigen::VectorXd(bp - A * bt) : bp).transpose();
  }
  const Eigen::MatrixXd Vinv = pseudo_inverse(r.efficient_information, r.dof);
  r.statistic = std::max(0.0, double(r.efficient_score.dot(Vinv * r.efficient_score)));
  if (np == 1 && r.efficient_information(0, 0) > 0.0)
    r.z = r.efficient_score(0) / std::sqrt(r.efficient_information(0, 0));
  const Eigen::VectorXd step = Vinv * r.efficient_score;
  for (Eigen::Index a = 0; a < np; ++a) {
    const double v0 = p.initial()[std::size_t(psi[std::size_t(a)])];
    r.null_value.push_back(v0);
    r.estimate.push_back(v0 + step(a));
    r.stderrs.push_back(Vinv(a, a) > 0.0 ? std::sqrt(Vinv(a, a)) : 0.0);
  }
  r.log_likelihood = d.log_likelihood;
  r.observations = ev.observations();
  r.substeps = ev.settings().substeps;
  return r;
}

}  // namespace vehs::likelihood
