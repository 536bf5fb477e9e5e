#pragma once
// The next fit as a file: diagnose-vehs writes, beside its report, an identify-vehs config that
// refits the diagnosed model with the recommended effects, ready to run as it is
// (`identify-vehs <report>/refit.json`): the keys of refit_config (tools/diagnosis_file.hpp) with
// the diagnosis's own measurement keys (data, columns, units, ...) and an output of its own.
#include <string>

#include <nlohmann/json.hpp>

#include "tools/config.hpp"
#include "vehs/core/model.hpp"
#include "vehs/diagnose/diagnose.hpp"

namespace vehs::tools {

/// Where diagnose-vehs writes the refit config: the config's `refit`, else <report>/refit.json.
std::string refit_config_path(const Config& diagnose_config, const std::string& report_folder);

/// The complete identify-vehs config, or null when the diagnosis recommends nothing (refit_config
/// null). Its `output` is refit_model.json in the folder of `path`; its measurement keys are the
/// diagnose config's (globs in `data` kept as patterns); `units` (the diagnosis's: its config's,
/// else the model file's) are written when the config's measurement keys lack them.
nlohmann::ordered_json refit_identify_config(const Config& diagnose_config, const diagnose::Result& result,
                                             const Model& model, const std::string& path,
                                             const nlohmann::ordered_json& units);

}  // namespace vehs::tools
