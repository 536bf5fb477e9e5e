#pragma once
// The sections identify-vehs writes into a model file besides the model itself: estimator (and
// why it was chosen), sampling (the diagnosis and how to read it), residuals, selection (the
// sparse-regression paths with BIC and CV figures), fit (rows, conditioning, standard-error
// method, timing), effect_params and dynamic_fit — all from the typed identify::Result.
#include <nlohmann/json.hpp>

#include "vehs/identify/identify.hpp"

namespace vehs::tools {

/// The report sections in file order (write them with vehs::write_model_file, which adds the
/// typed Model::fit over "estimator" and "sampling").
nlohmann::ordered_json identify_report_sections(const identify::Result& result);

}  // namespace vehs::tools
