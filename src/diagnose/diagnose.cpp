// diagnose(): the stages of comparison.hpp in order — the model against its twins, then the
// suspects, the verdict and the confirmation of close contenders.
#include "vehs/diagnose/diagnose.hpp"

#include <cmath>
#include <optional>
#include <vector>

#include "comparison.hpp"
#include "vehs/core/detail/progress_counter.hpp"
#include "vehs/core/error.hpp"

namespace vehs::diagnose {

std::string Options::invalid_reason() const {
  if (stride < 0) return "stride must be >= 0";
  if (lens == LensChoice::Forward && stride > 1) return "stride applies to central kinematics only";
  if (replicates < 0 || replicates > 1000) return "replicates must be in [0, 1000]";
  if (twin_substeps < 0) return "twin_substeps must be >= 0";
  if (map_bins_x < 2 || map_bins_v < 2 || map_bins_x > 200 || map_bins_v > 200)
    return "map bins must be in [2, 200] per axis";
  if (!(min_bin_count >= 10)) return "min_bin_count must be >= 10";
  if (min_units < 4) return "min_units must be >= 4";
  if (residual_lags < 1) return "residual_lags must be >= 1";
  if (!(alpha > 0.0 && alpha < 0.5)) return "alpha must be in (0, 0.5)";
  if (fpk_cells < 20 || fpk_cells > 2000) return "fpk_cells must be in [20, 2000]";
  if (!(expected_dt >= 0.0)) return "dt must be > 0";
  if (!(suspect_samples >= 0.0)) return "suspect_samples must be >= 0";
  if (parameter_draws < 2 || parameter_draws > 200) return "parameter_draws must be in [2, 200]";
  if (!(parameter_fit_samples >= 1e4)) return "parameter_fit_samples must be >= 10000";
  if (auto why = score_suspects.invalid_reason(); !why.empty()) return why;
  if (auto why = confirm.invalid_reason(); !why.empty()) return why;
  for (const auto& u : user_effects) {
    if (auto why = u.invalid_reason(); !why.empty()) return "user_effects: " + why;
    if (find_user_effect(user_effects, u.name) != &u) return "user_effects: '" + u.name + "' is listed twice";
  }
  return suspects.invalid_reason();
}

namespace detail {

/// A stage without units of its own: its name and elapsed time while it runs (heartbeat).
using Phase = vehs::detail::ProgressCounter;

Result compare_with_twins(const Model& model, const Dataset& data, const Options& opt, Stopwatch& watch) {
  if (auto why = opt.invalid_reason(); !why.empty()) throw Error("diagnose: " + why);
  validate_model(model, "model");
  require(!model.diffusion.empty(),
          "the model has no diffusion terms: its one-step residuals cannot be whitened and its "
          "twins cannot be simulated (the model file needs a 'diffusion' object)");
  require(!model.drift.empty(), "the model has no drift terms (the model file needs a 'drift' object)");
  require(!data.records.empty(), "no records to diagnose");
  if (model.uses_drive())
    require(data.has_u(),
            "the model has a drive term 'u' but the data have no drive column (name it with "
            "'columns': {\"u\": ...})");
  RecordChecks checks;
  checks.expected_dt = opt.expected_dt;
  check_records(data, checks);

  Result res;
  res.records = data.records.size();
  res.samples = data.total_samples();
  std::optional<Phase> setup(std::in_place, opt.progress, "diagnose setup", 0, true);
  const SamplingChoice sampling = choose_sampling_and_lens(model, data, opt, res);
  watch.lap(res, "sampling_pilot");
  Comparison cmp(model, data, opt, sampling.lens);
  cmp.plan = plan_units(data, sampling.lens, opt.min_units, res);
  make_setup(cmp, res);
  setup.reset();
  watch.lap(res, "setup");
  compute_statistics(cmp, sampling.verdict, res, watch);

  // ---- tests: the one-step map, the paired components (with the model's parameter
  // uncertainty where it matters), the residual lines
  std::optional<Phase> tests(std::in_place, opt.progress, "diagnose tests", 0, true);
  res.components.push_back(one_step_test(cmp, res.map));
  const std::vector<PairedStatistic> paired = paired_statistics(cmp.setup, cmp.units());
  tests.reset();
  watch.lap(res, "tests_setup");
  std::vector<ExtraCovariance> extra;
  const int draws = parameter_uncertainty(cmp, paired, extra, res);
  watch.lap(res, "parameter_draws");
  for (std::size_t k = 0; k < paired.size(); ++k) {
    const Eigen::MatrixXd D = unit_differences(paired[k].f, cmp.data_stats, cmp.twin_stats, paired[k].p);
    const bool with = draws > 0 && paired[k].parameter_sensitive;
    res.components.push_back({paired[k].name, paired[k].what, hotelling_zero_mean(D, 1e-9, with ? &extra[k] : nullptr)});
  }
  res.components.push_back(residual_line_test(cmp));
  add_quantities(cmp, res);
  watch.lap(res, "tests");

  // ---- what the report shows
  Phase curves(opt.progress, "diagnose curves and fpk", 0, true);
  add_curves(cmp, res);
  add_fpk_reference(cmp, res);
  watch.lap(res, "fpk_reference");
  return res;
}

}  // namespace detail

Result diagnose(const Model& model, const Dataset& data, const Options& given) {
  using detail::Phase;
  detail::Stopwatch watch;
  Options opt = given;  // the user's effects are suspects of both kinds
  for (auto* list : {&opt.suspects.user_effects, &opt.score_suspects.user_effects})
    for (const UserEffect& u : given.user_effects)
      if (!find_user_effect(*list, u.name)) list->push_back(u);
  Result res = detail::compare_with_twins(model, data, opt, watch);
  res.user_effects = given.user_effects;
  std::optional<Dataset> suspect_subset;
  if (opt.suspects.enabled) suspect_subset = detail::add_suspects(model, data, opt, res, watch);
  if (opt.score_suspects.enabled) {
    Phase phase(opt.progress, "score tests", 0, true);  // a step per effect tested
    Options counted = opt;
    counted.score_suspects.tested = [&phase] { phase.advance(); };
    detail::add_score_suspects(model, data, counted, res, watch);
  }
  detail::finish_verdict(res, opt.alpha);
  const bool bad = !res.adequate();
  if (bad && opt.suspects.enabled && opt.suspects.confirm) {
    Phase phase(opt.progress, "contender refits", 0, true);
    detail::confirm_contenders(model, suspect_subset ? *suspect_subset : data, res.lens, opt, res.suspects);
    watch.lap(res, "suspects_confirmation");
  }
  // a suspect is only claimed when the model is found inadequate
  for (auto& sp : res.suspects.ranked) sp.significant = sp.held_out_significant && bad;
  const bool refits = bad && opt.confirm.enabled;
  if (refits) {
    Phase phase(opt.progress, "confirmation refits", 0, true);
    detail::confirm_suspects(model, data, opt, res, watch);
  }
  detail::conclude(res, refits);
  res.timings.emplace_back("total", watch.total_seconds());
  return res;
}

}  // namespace vehs::diagnose
