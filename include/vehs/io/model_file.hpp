#pragma once
// Model files (docs/model-file.md): JSON with "drift" and "diffusion" ({term name: coefficient}),
// "stderr" ({"drift": {...}, "diffusion": {...}}), "effects" ([{"name", "params", "stderr"}]),
// "covariance" ({"parameters": ["drift[x]", "diffusion[1]", "impact_stop.gap", ...], "matrix":
// [[...], ...]}: the covariance of the estimates, Model::covariance),
// the fit ("estimator": {"used", "stride", ...}, "sampling": {"dt", "pilot_stride", "rho_lag1",
// "rho_lag_k", "rho_lag_2k", "rho_lag_3k", "noise_share", "verdict", "sensor_noise_sd", ...};
// Model::fit), and any other sections (identify-vehs writes its report there: residuals,
// selection, fit, data, provenance). The library interprets only the model and its fit; the
// other sections are kept in file order so that tools can copy a model file faithfully.
#include <string>

#include <nlohmann/json.hpp>

#include "vehs/core/model.hpp"
#include "vehs/core/user_effect.hpp"

namespace vehs {

/// A model and the sections of its file the library does not interpret (including the full
/// "estimator" and "sampling" objects, of which Model::fit holds the typed part).
struct ModelFile {
  Model model;
  nlohmann::ordered_json sections = nlohmann::ordered_json::object();
};

/// Parses a model object. `where` prefixes error messages (a file name or "config.json: model").
/// With `sections`, the keys other than drift, diffusion, stderr and effects are stored there.
Model model_from_json(const nlohmann::json& j, const std::string& where,
                      nlohmann::ordered_json* sections = nullptr);
/// Reads a model file.
ModelFile read_model_file(const std::string& path);
Model load_model_file(const std::string& path);
/// A config's `model` value: an inline object or the path of a model file.
ModelFile model_from_config_value(const nlohmann::json& value, const std::string& where);

/// Serialises a model (zero coefficients are omitted), then `sections` in their order; the
/// typed fit (Model::fit) is written into "estimator" and "sampling", over the values of
/// `sections` with the same keys.
nlohmann::ordered_json model_to_json(const Model& m,
                                     const nlohmann::ordered_json& sections = nlohmann::ordered_json::object());
/// Writes model_to_json atomically.
void write_model_file(const std::string& path, const Model& m,
                      const nlohmann::ordered_json& sections = nlohmann::ordered_json::object());

/// Parses one effect entry ({"name": ..., "params": {...}} or just "name");
/// `require_params` false allows params to be missing (identify fits them).
Effect effect_from_json(const nlohmann::json& j, const std::string& where, bool require_params);
nlohmann::ordered_json effect_to_json(const Effect& e);

/// Whether an effects entry is a user effect: an object with "drift" or "diffusion".
bool is_user_effect_json(const nlohmann::json& j);
/// Parses a user effect {"name": ..., "drift": {"param": "term", ...}, "diffusion": {...}}
/// (vehs/core/user_effect.hpp); errors name `where` and the key.
UserEffect user_effect_from_json(const nlohmann::json& j, const std::string& where);
nlohmann::ordered_json user_effect_to_json(const UserEffect& e);

}  // namespace vehs
