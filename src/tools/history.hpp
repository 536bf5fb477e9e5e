#pragma once
// The model history of a report folder: each diagnose run appends the model it diagnosed and its
// score, so the report can plot the discrepancy falling as the user adds effects.
//
// File: JSON {"entries": [...]} written atomically; every entry holds the run time, a label,
// the model file, the model itself (docs/model-file.md) and a hash of it, the terms and effects, the verdict, the score and
// its components, and a fingerprint of the data (records, samples, dt and a hash of sampled
// values). Scores are only comparable for the same data: the plot keeps the entries whose
// fingerprint equals the current one.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vehs/core/model.hpp"
#include "vehs/diagnose/diagnose.hpp"
#include "vehs/core/dataset.hpp"

namespace vehs::tools {

/// A short hex fingerprint of the data (record sizes, dt and a sample of values).
std::string data_fingerprint(const Dataset& data);
/// A short hex hash of a model's drift, diffusion and effects.
std::string model_hash(const Model& model);

/// The entry of one run; `model_sections` are the other sections of the model's file (kept in
/// the stored copy of the model).
nlohmann::ordered_json history_entry(const Model& model, const std::string& model_file, const std::string& label,
                                     const Dataset& data, const diagnose::Result& result,
                                     const nlohmann::ordered_json& model_sections = nlohmann::ordered_json::object());

/// Reads the history file (empty when it does not exist), after repairing its folder's stale
/// staging folders (recover_stale_outputs); throws vehs::Error naming the file when it exists but
/// is not a history file.
std::vector<nlohmann::ordered_json> read_history(const std::string& path);

/// Appends `entry` (numbering it as version n + 1 of its data fingerprint) and writes the file
/// atomically. Inside an output transaction the file is locked (OutputTransaction::lock_output,
/// `<path>.lock`) from the read until the run's commit: concurrent runs keep every entry.
/// Returns all entries.
std::vector<nlohmann::ordered_json> append_history(const std::string& path, nlohmann::ordered_json entry);

}  // namespace vehs::tools
