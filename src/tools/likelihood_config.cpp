#include "tools/likelihood_config.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "vehs/core/detail/format.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/standard_errors.hpp"
#include "vehs/likelihood/input_reading.hpp"
#include "vehs/likelihood/record_phase_start.hpp"
#include "vehs/likelihood/signals.hpp"

namespace vehs::tools {

const char* const kLikelihoodHelp =
    "Refinement of the moment fit by maximum likelihood (exact at the data's sampling: a "
    "continuous-discrete Gaussian filter over the model's state, Ceres BFGS with automatic "
    "derivatives; vehs/likelihood/refine.hpp). Used when estimator is \"likelihood\", when this "
    "block is given, and with estimator \"auto\" whenever the sampling cannot vouch for the "
    "moment estimators (omega*dt >= 0.2 with a bias (omega*dt)^2/12 above the best relative "
    "standard error, or a recorded input with omega*dt >= 0.1; omega from the lag-1 and lag-2 "
    "increments of x, insensitive to sensor noise; see vehs/likelihood/adequacy.hpp). Keys: "
    "use (\"auto\", \"always\", \"never\"; default \"always\" when the block is given), input "
    "(how the recorded input is applied between samples: \"zoh\", \"linear\", \"cubic\", "
    "\"band_limited\", or \"auto\" (default): band_limited when less than 10 % of the input's power lies "
    "above 3/4 of the Nyquist frequency (a smooth signal that was sampled, e.g. a measured base "
    "acceleration), else zoh (a sequence held by a DAC), then the higher log-likelihood of brief fits "
    "under zoh and band_limited decides (records of at least 16 samples); carried in the model file and used by "
    "simulate-vehs, its validation and diagnose-vehs), "
    "select (true: forward steps by the score test over the drift and diffusion libraries, then backward elimination, by the criterion), "
    "criterion (\"bic\" or \"lr\": likelihood-ratio test at level lr_alpha, default 1e-3), "
    "covariance (standard errors: \"observed\" information, \"fisher\", \"sandwich\"), "
    "measurement_noise (true: estimate white sensor noise on x), per_record_phase (true: one "
    "harmonic_forcing phase per record, amplitude and omega shared; records started at unrelated "
    "times), substeps (RK4 substeps per interval, 0: automatic), max_rounds, bias_correction (B > 0: "
    "remove the Gaussian filter's own bias by B data sets simulated at the estimate, standard errors "
    "x sqrt(1 + 1/B); at B = 8 +25 % CPU on the paper's model, 3.6x on Silverbox, whose interpolated "
    "input is simulated at 96 steps per interval; 0: off; default \"auto\": B = 8 when the fit estimates "
    "sensor noise and resolves it (above 2 SE), where the filter over-estimates a multiplicative noise by about 5 %, else 0, and "
    "skipped with the reason when the estimate cannot be simulated), bias_correction_seed (seed of "
    "the first simulated data set, default 1). The model file then holds \"likelihood\": "
    "measurement_sd, record_phases, log_likelihood, bic, observations, the parameters with their "
    "covariance matrix, bias_correction (datasets, seed, max_shift_se, or why it was skipped), and "
    "estimator.input.";

namespace {

LikelihoodUse use_from_string(const Config& c, const std::string& key, const std::string& s) {
  if (s == "auto") return LikelihoodUse::Auto;
  if (s == "always") return LikelihoodUse::Always;
  if (s == "never") return LikelihoodUse::Never;
  c.fail(key, "must be \"auto\", \"always\" or \"never\" (got \"" + s + "\")");
}

}  // namespace

std::string moment_estimator_name(const Config& c) {
  const std::string e = c.string_or("estimator", "auto");
  if (e == "likelihood") return "auto";
  for (const auto& [id, name] : kEstimatorNames)
    if (name == e) return e;
  c.fail("estimator", "must be one of " + enum_choices(kEstimatorNames) + ", likelihood (got '" + e + "')");
}

LikelihoodSettings likelihood_settings(const Config& c) {
  LikelihoodSettings s;
  const std::string estimator = c.string_or("estimator", "auto");
  s.use = estimator == "likelihood" ? LikelihoodUse::Always
          : estimator == "auto"     ? LikelihoodUse::Auto
                                    : LikelihoodUse::Never;
  auto& o = s.options;
  if (!c.has("likelihood")) return s;
  const Config l = c.object("likelihood", {"use", "input", "select", "criterion", "lr_alpha", "covariance",
                                           "measurement_noise", "per_record_phase", "substeps", "max_rounds",
                                           "bias_correction", "bias_correction_seed"});
  s.use = use_from_string(l, "use", l.string_or("use", "always"));
  if (estimator == "likelihood" && s.use != LikelihoodUse::Always)
    l.fail("use", "contradicts estimator \"likelihood\"");
  const std::string input = l.string_or("input", "auto");
  s.input_auto = input == "auto";
  if (!s.input_auto) o.filter.input = enum_from_string(kInputInterpolationNames, input, l.where("input"));
  o.select = l.boolean_or("select", true);
  o.criterion = enum_from_string(likelihood::kSelectionCriterionNames, l.string_or("criterion", "bic"),
                                 l.where("criterion"));
  o.lr_alpha = l.number_or("lr_alpha", 1e-3);
  o.covariance = enum_from_string(likelihood::kCovarianceNames, l.string_or("covariance", "observed"),
                                  l.where("covariance"));
  o.estimate_measurement_noise = l.boolean_or("measurement_noise", true);
  o.per_record_phase = l.boolean_or("per_record_phase", false);
  const long long sub = l.integer_at_least("substeps", 0, 0);
  if (sub > 1000) l.fail("substeps", "must be <= 1000");
  o.filter.substeps = static_cast<int>(sub);
  o.max_rounds = l.int_at_least("max_rounds", 1, 20);
  if (l.has("bias_correction") && !(l.raw("bias_correction").is_string() && l.string("bias_correction") == "auto")) {
    if (l.raw("bias_correction").is_string())
      l.fail("bias_correction", "must be \"auto\" or an integer B in [0, 1000] (got \"" + l.string("bias_correction") + "\")");
    const long long bias_sets = l.integer_at_least("bias_correction", 0, 0);
    if (bias_sets > 1000) l.fail("bias_correction", "must be <= 1000");
    o.bias_correction_datasets = static_cast<int>(bias_sets);
    o.bias_correction_auto = false;
  }
  o.bias_correction_seed = static_cast<std::uint64_t>(l.integer_at_least("bias_correction_seed", 0, 1));
  std::string why;
  if (!o.IsValid(&why)) throw Error(c.where("likelihood") + ": " + why);
  return s;
}

}  // namespace vehs::tools
