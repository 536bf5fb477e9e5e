// The model's parameter uncertainty in a diagnosis: the model's terms (and dynamic effects) are
// refitted by identify on pseudo-data simulated from the model, each refit is resimulated with
// the random numbers of twin replicate 0, and the covariance of the shifts of the
// parameter-sensitive statistics (rescaled to the data size) is added to their tests.
#include <exception>
#include <string>

#include "comparison.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/record_phases.hpp"
#include "vehs/core/detail/progress_counter.hpp"
#include "vehs/identify/identify.hpp"

namespace vehs::diagnose::detail {

int parameter_uncertainty(const Comparison& cmp, const std::vector<PairedStatistic>& paired,
                          std::vector<ExtraCovariance>& extra, Result& res) {
  const Model& model = cmp.model;
  const Dataset& data = cmp.data;
  const Options& opt = cmp.options;
  const Lens& lens = cmp.lens;
  const StatsSetup& setup = cmp.setup;
  const std::vector<UnitSpan>& units = cmp.plan.units;
  const std::vector<UnitStats>& rep0 = cmp.twin_rep0;
  const TwinSettings& ts = cmp.twin_settings;
  extra.assign(paired.size(), ExtraCovariance{});
  int draws = 0;
  const bool fitted = !model.drift_stderr.empty() || !model.diffusion_stderr.empty();
  const bool use = opt.parameter_uncertainty == ParameterUncertainty::On ||
                   (opt.parameter_uncertainty == ParameterUncertainty::Auto && fitted);
  if (use) {
    // pseudo-data: twins of the first records, at most parameter_fit_samples samples
    const auto limit = static_cast<std::size_t>(opt.parameter_fit_samples);
    const Dataset sub = leading_samples(data, [&](std::size_t, const Record& r, std::size_t taken) {
      const std::size_t n = taken < limit ? std::min(r.size, limit - taken) : 0;
      return n < 64 ? kEndSelection : n;
    });
    const double scale = static_cast<double>(sub.x.size()) / static_cast<double>(res.samples);
    // the model's terms and dynamic effects (all params free) as the lens sees them; an identify
    // that cannot fit an effect throws, and the warning below says the uncertainty is not propagated
    const identify::Options io = refit_options(model, lens);
    TwinSettings ps = ts;
    ps.seed = ts.seed ^ 0x5EED5EED5EEDull;
    TwinSimulator pseudo_sim(model, sub, ps);
    std::vector<Eigen::MatrixXd> acc(paired.size()), acc_within(paired.size());
    std::vector<double> acc_units(paired.size(), 0.0);
    for (std::size_t k = 0; k < paired.size(); ++k) {
      acc[k] = Eigen::MatrixXd::Zero(paired[k].p, paired[k].p);
      acc_within[k] = acc[k];
    }
    Dataset pseudo, star_twin;
    std::vector<UnitStats> star(units.size());
    vehs::detail::ProgressCounter pprog(opt.progress, "parameter draws", opt.parameter_draws);
    int rejected = 0;
    std::string rejection;
    try {
      if (!record_phases_of(model).empty())  // identify's moment fit has one shared phase
        throw Error("a harmonic_forcing phase per record cannot be refitted by the moment estimators");
      for (int attempt = 0; draws < opt.parameter_draws; ++attempt) {
        // a draw whose refit fails (an estimate outside the model's domain, a22 < 0 where its twin
        // goes) is rejected and redrawn from the next pseudo-data: one failure no longer drops the
        // uncertainty; the replicates before the first failure are those of a run without one
        try {
          pseudo_sim.simulate(attempt, pseudo);
          const Model mstar = identify::identify(pseudo, io).model;
          TwinSimulator star_sim(mstar, data, ts);  // same seed as twin replicate 0
          star_sim.simulate(0, star_twin);
        } catch (const std::exception& e) {
          if (rejected++ == 0) rejection = e.what();
          if (rejected > opt.parameter_draws) throw Error(std::to_string(rejected) + " draws failed: " + rejection);
          continue;
        }
#pragma omp parallel for schedule(dynamic, 1)
        for (long j = 0; j < static_cast<long>(units.size()); ++j) {
          const UnitSpan& sp = units[static_cast<std::size_t>(j)];
          const Record& rec = star_twin.records[sp.record];
          compute_unit(setup, star_twin.x_of(rec),
                               model.uses_drive() ? data.u_of(data.records[sp.record]) : nullptr, rec.size,
                               rec.t0, sp, star[static_cast<std::size_t>(j)], true);
        }
        for (std::size_t k = 0; k < paired.size(); ++k) {
          if (!paired[k].parameter_sensitive) continue;
          const Eigen::MatrixXd De = unit_differences(paired[k].f, star, rep0, paired[k].p);
          if (De.rows() < 3) continue;
          const Eigen::VectorXd e = De.colwise().mean().transpose();
          const Eigen::MatrixXd Ce = De.rowwise() - e.transpose();
          const double n = static_cast<double>(De.rows());
          acc[k] += e * e.transpose();
          acc_within[k] += (Ce.transpose() * Ce) / ((n - 1.0) * n);
          acc_units[k] += n;
        }
        ++draws;
        pprog.advance();
      }
      if (rejected > 0)
        res.warnings.push_back(std::to_string(rejected) + " of " + std::to_string(draws + rejected) +
                               " parameter draws were rejected and redrawn (the first: " + rejection + ")");
    } catch (const std::exception& e) {
      res.warnings.push_back(std::string("the model's parameter uncertainty could not be estimated (") + e.what() +
                             "); the stationary tests ignore it");
      draws = 0;
    }
    pprog.finish();
    if (draws > 0)
      for (std::size_t k = 0; k < paired.size(); ++k) {
        if (!paired[k].parameter_sensitive) continue;
        // the refits used `scale` times the data's samples: their parameter covariance is 1/scale
        // times the data's
        ExtraCovariance ec;
        ec.second_moment = acc[k] / draws;
        ec.within = acc_within[k] / draws;
        ec.draws = draws;
        ec.units = acc_units[k] / draws;
        extra[k] = ec.scaled(scale);
      }
    res.parameter_draws = draws;
    res.parameter_fit_samples = sub.x.size();
  }
  return draws;
}

}  // namespace vehs::diagnose::detail
