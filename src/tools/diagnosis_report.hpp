#pragma once
// The report page of a diagnosis: every figure (gnuplot SVG + its CSV + its script) and table,
// with captions that say how to read them.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vehs/diagnose/diagnose.hpp"
#include "tools/html_report.hpp"

namespace vehs::tools {

/// Adds the sections of `result` to `report`. `history` are the entries of the model history
/// (history.hpp); those with the fingerprint `fingerprint` are plotted as the score over model
/// versions. `model_label` names the diagnosed model.
void add_diagnosis_to_report(Report& report, const diagnose::Result& result, const std::string& model_label,
                             const std::vector<nlohmann::ordered_json>& history, const std::string& fingerprint);

}  // namespace vehs::tools
