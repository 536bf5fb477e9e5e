#pragma once
// The JSON of diagnose-vehs: verdict, score, components, suspects, and every detail of the tests.
#include <string>

#include <nlohmann/json.hpp>

#include "vehs/diagnose/diagnose.hpp"

namespace vehs::tools {

nlohmann::ordered_json diagnosis_to_json(const diagnose::Result& result);

/// The fragment to merge into an identify-vehs config to fit a suspect: {"effects": [{"name": ...}]}.
nlohmann::ordered_json suspect_add_fragment(const diagnose::Suspect& suspect);

/// How the outputs spell a sampling verdict and an estimator; empty when not known.
std::string verdict_text(SamplingVerdict verdict);
std::string estimator_text(Estimator estimator);

}  // namespace vehs::tools
