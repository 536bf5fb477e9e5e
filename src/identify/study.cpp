#include "vehs/identify/study.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <limits>
#include <set>
#include <sstream>

#include "vehs/core/error.hpp"
#include "vehs/core/parameters.hpp"
#include "vehs/core/detail/progress_counter.hpp"

namespace vehs::identify {

std::string StudyOptions::invalid_reason() const {
  if (points.empty()) return "the study needs at least one grid point";
  for (const auto& p : points) {
    if (!(p.dt > 0.0) || !std::isfinite(p.dt)) return "every dt must be > 0";
    if (p.samples < 100) return "every sample count must be >= 100";
  }
  if (repeats < 2) return "repeats must be >= 2 (a standard deviation needs two)";
  if (records < 1) return "records must be >= 1";
  if (substeps < 1) return "substeps must be >= 1";
  if (!(sensor_noise >= 0.0)) return "sensor_noise must be >= 0";
  if (truth.drift.empty()) return "the truth model has no drift terms";
  return identify.invalid_reason();
}

namespace {

std::set<std::string> term_set(const TermList& l) {
  std::set<std::string> s;
  for (const auto& tc : l)
    if (tc.coef != 0.0) s.insert(tc.term.name());
  return s;
}

}  // namespace

StudyResult run_study(const StudyOptions& o) {
  if (auto why = o.invalid_reason(); !why.empty()) throw Error("study: " + why);
  const auto truth_params = physical_parameters(o.truth);
  const auto truth_drift = term_set(o.truth.drift), truth_diff = term_set(o.truth.diffusion);
  StudyResult res;
  vehs::detail::ProgressCounter progress(o.progress, "study", static_cast<long long>(o.points.size()) * o.repeats);
  long long covered = 0;
  for (std::size_t pi = 0; pi < o.points.size(); ++pi) {
    const StudyPoint& pt = o.points[pi];
    StudyPointResult pr;
    pr.point = pt;
    const std::size_t np = truth_params.size();
    std::vector<std::vector<double>> est(np), se(np);
    int exact = 0;
    for (int rep = 0; rep < o.repeats; ++rep) {
      sim::SimulationOptions so;
      so.dt = pt.dt;
      so.substeps = o.substeps;
      so.samples = pt.samples;
      so.records = o.records;
      so.scheme = o.scheme;
      so.seed = o.seed + 1000003ULL * pi + 7919ULL * static_cast<std::uint64_t>(rep);
      so.x0 = o.x0;
      so.burn_in = o.burn_in;
      so.sensor_noise = o.sensor_noise;
      so.record_y = false;
      const auto t0 = std::chrono::steady_clock::now();
      const Dataset data = sim::simulate(o.truth, so);
      const auto t1 = std::chrono::steady_clock::now();
      const Result r = identify(data, o.identify);
      const auto t2 = std::chrono::steady_clock::now();
      pr.seconds_simulate += std::chrono::duration<double>(t1 - t0).count();
      pr.seconds_identify += std::chrono::duration<double>(t2 - t1).count();
      pr.estimators_used.push_back(enum_to_string(kEstimatorNames, r.model.fit->estimator));
      if (term_set(r.model.drift) == truth_drift && term_set(r.model.diffusion) == truth_diff) ++exact;
      const auto learned = physical_parameters(r.model);
      for (std::size_t i = 0; i < np; ++i) {
        double v = 0.0, s = std::numeric_limits<double>::quiet_NaN();
        for (const auto& lp : learned)
          if (lp.name == truth_params[i].name) {
            v = lp.value;
            if (lp.stderr_) s = *lp.stderr_;
          }
        est[i].push_back(v);
        se[i].push_back(s);
      }
      progress.advance(1);
    }
    pr.support_exact = static_cast<double>(exact) / o.repeats;
    for (std::size_t i = 0; i < np; ++i) {
      StudyParameter sp;
      sp.name = truth_params[i].name;
      sp.truth = truth_params[i].value;
      double m = 0.0, mse = 0.0;
      int cover = 0, nse = 0;
      for (int r = 0; r < o.repeats; ++r) {
        m += est[i][static_cast<std::size_t>(r)] / o.repeats;
        const double s = se[i][static_cast<std::size_t>(r)];
        if (std::isfinite(s)) {
          mse += s;
          ++nse;
          if (std::abs(est[i][static_cast<std::size_t>(r)] - sp.truth) <= 1.96 * s) ++cover;
        }
      }
      double var = 0.0;
      for (int r = 0; r < o.repeats; ++r) var += std::pow(est[i][static_cast<std::size_t>(r)] - m, 2);
      sp.mean = m;
      sp.sd = std::sqrt(var / (o.repeats - 1));
      sp.mean_stderr = nse > 0 ? mse / nse : std::numeric_limits<double>::quiet_NaN();
      sp.coverage = static_cast<double>(cover) / o.repeats;
      covered += cover;
      res.intervals += o.repeats;
      pr.parameters.push_back(sp);
    }
    res.points.push_back(pr);
  }
  progress.finish();
  res.coverage = res.intervals > 0 ? static_cast<double>(covered) / static_cast<double>(res.intervals) : 0.0;
  return res;
}

}  // namespace vehs::identify
