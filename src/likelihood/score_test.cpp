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

namespace {

/// The C(α) test of the parameters `psi` against the nuisance ones `theta` (indices into the
/// parameter vector) from one derivative pass.
ScoreTestResult efficient_test(const detail::Parameterization& p, const detail::Derivatives& d,
                               const std::vector<Eigen::Index>& psi, const std::vector<Eigen::Index>& theta) {
  const Eigen::MatrixXd& F = d.fisher;
  const Eigen::VectorXd& g = d.gradient;
  const Eigen::Index np = Eigen::Index(psi.size()), nt = Eigen::Index(theta.size());
  auto at = [](const std::vector<Eigen::Index>& v, Eigen::Index i) { return v[std::size_t(i)]; };
  Eigen::MatrixXd Fpp(np, np), Fpt(np, nt), Ftt(nt, nt);
  Eigen::VectorXd gp(np), gt(nt);
  for (Eigen::Index a = 0; a < np; ++a) {
    gp(a) = g(at(psi, a));
    for (Eigen::Index b = 0; b < np; ++b) Fpp(a, b) = F(at(psi, a), at(psi, b));
    for (Eigen::Index b = 0; b < nt; ++b) Fpt(a, b) = F(at(psi, a), at(theta, b));
  }
  for (Eigen::Index a = 0; a < nt; ++a) {
    gt(a) = g(at(theta, a));
    for (Eigen::Index b = 0; b < nt; ++b) Ftt(a, b) = F(at(theta, a), at(theta, b));
  }
  int rank_t = 0;
  const Eigen::MatrixXd A = nt > 0 ? Eigen::MatrixXd(Fpt * pseudo_inverse(Ftt, rank_t))
                                   : Eigen::MatrixXd(np, 0);  // F_ψθ F_θθ⁻¹
  ScoreTestResult r;
  for (Eigen::Index a = 0; a < np; ++a) r.tested.push_back(p.parameters()[std::size_t(at(psi, a))].name);
  r.efficient_score = nt > 0 ? Eigen::VectorXd(gp - A * gt) : gp;
  r.efficient_information = nt > 0 ? Eigen::MatrixXd(Fpp - A * Fpt.transpose()) : Fpp;
  const Eigen::MatrixXd& B = d.batch_scores;  // records × parameters
  r.record_scores.resize(B.rows(), np);
  for (Eigen::Index k = 0; k < B.rows(); ++k) {
    Eigen::VectorXd bp(np), bt(nt);
    for (Eigen::Index a = 0; a < np; ++a) bp(a) = B(k, at(psi, a));
    for (Eigen::Index a = 0; a < nt; ++a) bt(a) = B(k, at(theta, a));
    r.record_scores.row(k) = (nt > 0 ? Eigen::VectorXd(bp - A * bt) : bp).transpose();
  }
  const Eigen::MatrixXd Vinv = pseudo_inverse(r.efficient_information, r.dof);
  r.statistic = std::max(0.0, double(r.efficient_score.dot(Vinv * r.efficient_score)));
  if (np == 1 && r.efficient_information(0, 0) > 0.0)
    r.z = r.efficient_score(0) / std::sqrt(r.efficient_information(0, 0));
  const Eigen::VectorXd step = Vinv * r.efficient_score;
  for (Eigen::Index a = 0; a < np; ++a) {
    const double v0 = p.initial()[std::size_t(at(psi, a))];
    r.null_value.push_back(v0);
    r.estimate.push_back(v0 + step(a));
    r.stderrs.push_back(Vinv(a, a) > 0.0 ? std::sqrt(Vinv(a, a)) : 0.0);
  }
  r.log_likelihood = d.log_likelihood;
  return r;
}

}  // namespace

std::vector<ScoreTestResult> score_tests(const ObservedModel& model, const Dataset& data,
                                         const std::vector<std::vector<std::string>>& groups,
                                         const ScoreTestOptions& options) {
  const std::string where = "score test";
  std::vector<std::string> all;
  for (const auto& g : groups) {
    if (g.empty()) throw Error(where + ": an empty group of parameters to test");
    all.insert(all.end(), g.begin(), g.end());
  }
  if (all.empty()) throw Error(where + ": no parameter to test");
  if (const std::string why = options.filter.invalid_reason(); !why.empty())
    throw Error(where + ": " + why);
  detail::FitChoice choice;
  choice.fit_measurement_noise = options.estimate_measurement_noise && model.measurement_sd > 0.0;
  choice.per_record_phase = !model.record_phases.empty();  // the model's phases per record, free
  choice.fixed = options.fixed;
  choice.natural_scale = all;
  const detail::Parameterization p(model, choice, data.records.size(), where);
  detail::Evaluator ev(p, data, options.filter, where);
  ev.batch_samples = 0;  // one batch per record
  auto index_of = [&](const std::string& name) {
    const auto& ps = p.parameters();
    auto it = std::find_if(ps.begin(), ps.end(), [&](const ParameterInfo& q) { return q.name == name; });
    if (it == ps.end()) throw Error(where + ": '" + name + "' is not a free parameter of the model");
    return Eigen::Index(it - ps.begin());
  };
  std::vector<Eigen::Index> tested;
  for (const auto& name : all) tested.push_back(index_of(name));
  detail::Derivatives d;
  detail::EvaluationFailure f;
  if (!ev.derivatives(p.initial().data(), d, true, true, &f)) throw FilterDiverged(ev.message(f));
  std::vector<ScoreTestResult> out;
  for (const auto& g : groups) {
    // this group against the model's own parameters; the other groups stay at their null
    std::vector<Eigen::Index> psi, theta;
    for (const auto& name : g) psi.push_back(index_of(name));
    for (Eigen::Index i = 0; i < Eigen::Index(p.size()); ++i)
      if (std::find(tested.begin(), tested.end(), i) == tested.end()) theta.push_back(i);
    out.push_back(efficient_test(p, d, psi, theta));
    out.back().observations = ev.observations();
    out.back().substeps = ev.settings().substeps;
  }
  return out;
}

ScoreTestResult score_test(const ObservedModel& model, const Dataset& data,
                           const std::vector<std::string>& tested, const ScoreTestOptions& options) {
  return score_tests(model, data, {tested}, options).front();
}

}  // namespace vehs::likelihood
