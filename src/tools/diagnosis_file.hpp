#pragma once
// The JSON of diagnose-vehs: verdict, score, components, suspects, and every detail of the tests.
#include <nlohmann/json.hpp>

#include "vehs/diagnose/diagnose.hpp"

namespace vehs::tools {

nlohmann::ordered_json diagnosis_to_json(const diagnose::Result& result);

}  // namespace vehs::tools
