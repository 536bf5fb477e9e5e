#pragma once
// The report page of a diagnosis: every figure (gnuplot SVG + its CSV + its script) and table,
// with captions that say how to read them.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vehs/diagnose/diagnose.hpp"
#include "tools/html_report.hpp"

namespace vehs::tools {

/// Adds the sections of `result` to `report`: first a summary card (verdict, next step, the
/// parameters with standard errors and units; `next_command` when a refit config was written),
/// with `data` measured vs simulated under the recorded input and the residual–input
/// cross-correlation (report_validation.hpp). `history` are the entries of the model history
/// (history.hpp); those with the fingerprint `fingerprint` are plotted as the score over model
/// versions. `model_label` names the diagnosed model; `units` is the data's units block (axis
/// labels; may be empty); `versions` link the kept reports of every model version.
void add_diagnosis_to_report(Report& report, const diagnose::Result& result, const std::string& model_label,
                             const std::vector<nlohmann::ordered_json>& history, const std::string& fingerprint,
                             const nlohmann::json& units = nlohmann::json::object(),
                             const std::vector<ReportLink>& versions = {}, const Model* model = nullptr,
                             const Dataset* data = nullptr, const std::string& next_command = "");

/// The one-line next step of a diagnosis: what to change in the identify config (with `model`,
/// the diagnosed model, the complete keys of refit_config; else the effects to add), or that
/// nothing needs to change.
std::string next_step(const diagnose::Result& result, const Model* model = nullptr);

}  // namespace vehs::tools
