#pragma once
// Outputs of identify-vehs's consistency study: JSON, a CSV table (one row per grid point and
// parameter) and the seed paper's Table 4 layout as text.
#include <string>

#include <nlohmann/json.hpp>

#include "tools/table.hpp"
#include "vehs/identify/study.hpp"

namespace vehs::tools {

nlohmann::ordered_json study_to_json(const identify::StudyResult& study);
/// One row per (point, parameter): dt, samples, truth, mean, sd, mean_stderr, coverage.
Table study_table(const identify::StudyResult& study);
/// The paper's Table 4 layout: parameters down, grid points across, "mean (sd)".
std::string study_text(const identify::StudyResult& study);

}  // namespace vehs::tools
