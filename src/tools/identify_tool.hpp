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
#include "tools/likelihood_refinement.hpp"
#include "tools/recorded_input.hpp"
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

/// What identify-vehs fits: identify's result (its model refined by the likelihood when the
/// config asks for it or the sampling cannot vouch for the moment fit) and that decision.
struct IdentifyFit {
  identify::Result result;
  Refinement refinement;
  RecordedInput input;  ///< what was done with the data's input column
};

/// identify-vehs's fit of loaded (and detrended) data: the config's `samples` range is taken
/// first (into `ranged`, which then holds the data fitted), the default CV folds fit small data,
/// the likelihood logs its rounds to `log` (may be empty). The first step of identify_in_memory.
IdentifyFit identify_fit(const Config& c, const Dataset& data, const ProgressCallback& progress,
                         const std::function<void(const std::string&)>& log, std::optional<Dataset>& ranged);

/// identify-vehs's work on records in memory, everything but reading data and writing files:
/// identify_fit, the model checked for writing (errors name `where`) and the model file's report
/// sections, whose fit.in_memory_seconds is the wall time of all of it. Shared by identify-vehs
/// and vehs.identify, so that both do and time the same work (docs/model-file.md).
struct IdentifiedInMemory {
  IdentifyFit fit;
  nlohmann::ordered_json sections;
};
IdentifiedInMemory identify_in_memory(const Config& c, const Dataset& data, const ProgressCallback& progress,
                                      const std::function<void(const std::string&)>& log,
                                      std::optional<Dataset>& ranged, const std::string& where);

/// The body of identify-vehs: identification (or a consistency study when `study` is given).
int run_identify(Config& c, const AppOptions& app);

}  // namespace vehs::tools
