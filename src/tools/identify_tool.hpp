#pragma once
// identify-vehs: key table, options from a config, and the run (identification, or a consistency
// study when `study` is given), so that tests can drive the complete command-line path
// (config → data → model file) in-process.
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "tools/app.hpp"
#include "tools/config.hpp"
#include "tools/likelihood_config.hpp"
#include "vehs/fit/fit.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/identify/study.hpp"
#include "vehs/io/measurements.hpp"

namespace vehs::tools {

/// The key table of identify-vehs (docs/config.md plus the estimator settings).
const ConfigSchema& identify_schema();

/// Options of the estimator from a config (libraries, effects, estimator, sparsity...).
identify::Options identify_options(const Config& c);

/// Study options from the config's `study` object (no `data`, moment estimators only).
identify::StudyOptions study_options(const Config& c);

/// The fit's options from a config (vehs/fit/fit.hpp): identify_options, likelihood_settings, the
/// data checks' rules (applied when the data are read, not again by the fit) and which defaults
/// the config left to the data.
FitOptions fit_options(const Config& c);

/// identify-vehs's fit of loaded (and detrended) data by vehs::fit under `options` (fit_options of
/// the config, or vehs.FitOptions): the config's `samples` range is taken first (into `ranged`,
/// which then holds the data fitted), the likelihood logs its rounds to `log` (may be empty). The
/// first step of identify_in_memory.
vehs::FitSummary identify_fit(const Config& c, FitOptions options, const Dataset& data, const ProgressCallback& progress,
                              const std::function<void(const std::string&)>& log, std::optional<Dataset>& ranged);

/// identify-vehs's work on records in memory, everything but reading data and writing files:
/// identify_fit, the model checked for writing (errors name `where`) and the model file's report
/// sections, whose fit.in_memory_seconds is the wall time of all of it. Shared by identify-vehs
/// and vehs.identify, so that both do and time the same work (docs/model-file.md).
struct IdentifiedInMemory {
  vehs::FitSummary fit;
  nlohmann::ordered_json sections;
};
IdentifiedInMemory identify_in_memory(const Config& c, const FitOptions& options, const Dataset& data,
                                      const ProgressCallback& progress,
                                      const std::function<void(const std::string&)>& log,
                                      std::optional<Dataset>& ranged, const std::string& where);

/// The body of identify-vehs: identification (or a consistency study when `study` is given).
int run_identify(Config& c, const AppOptions& app);

}  // namespace vehs::tools
