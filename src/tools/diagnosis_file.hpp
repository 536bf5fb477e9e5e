#pragma once
// The JSON of diagnose-vehs: verdict, score, components, suspects, and every detail of the tests.
#include <string>

#include <nlohmann/json.hpp>

#include "vehs/diagnose/diagnose.hpp"

namespace vehs::tools {

/// With `model` (the diagnosed model) the JSON also holds `refit_config` (below).
nlohmann::ordered_json diagnosis_to_json(const diagnose::Result& result, const Model* model = nullptr);

/// The identify-vehs config keys that fit the model with the recommended effects as diagnose's
/// confirming refit did: the model's own terms as the libraries, its effects and the recommended
/// ones, no re-selection ("sparsity": "none"; "likelihood": {"select": false, ...} when the refits
/// were by the likelihood, with the model's input interpolation and one forcing phase per record
/// when so confirmed). Null when nothing was confirmed.
nlohmann::ordered_json refit_config(const diagnose::Result& result, const Model& model);

/// The fragment to merge into an identify-vehs config to fit a suspect: {"effects": [{"name": ...}]}
/// (a user's effect: its definition).
nlohmann::ordered_json suspect_add_fragment(const diagnose::Suspect& suspect, const std::vector<UserEffect>& user);

/// How the outputs spell a sampling verdict and an estimator; empty when not known.
std::string verdict_text(SamplingVerdict verdict);
std::string estimator_text(Estimator estimator);

}  // namespace vehs::tools
