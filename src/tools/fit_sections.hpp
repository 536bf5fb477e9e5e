#pragma once
// The model file's sections that describe vehs::fit's steps (docs/model-file.md): the sampling
// adequacy and the likelihood's use, its starts, and the data's input column.
#include <vector>

#include <nlohmann/json.hpp>

#include "vehs/fit/fit.hpp"

namespace vehs::tools {

/// estimator.sampling_adequacy: whether the likelihood refined the moment fit, and why.
nlohmann::ordered_json adequacy_json(const Refinement& f);

/// estimator.likelihood_starts: one object per start.
nlohmann::ordered_json likelihood_starts_json(const std::vector<LikelihoodStart>& starts);

/// data.input: {"column", "in_drift_library", "added", "why"} (null without an input).
nlohmann::ordered_json recorded_input_json(const RecordedInput& input);

}  // namespace vehs::tools
