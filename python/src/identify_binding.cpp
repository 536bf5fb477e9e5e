// vehs.identify: identify-vehs's estimator keys, records read in place.
#include <optional>

#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>

#include "bindings.hpp"
#include "bridge.hpp"
#include "records.hpp"
#include "tools/identify_tool.hpp"
#include "tools/likelihood_refinement.hpp"
#include "tools/measurement_config.hpp"
#include "tools/study_output.hpp"

namespace vehs::python {

namespace {

/// The records to work on: `records` after the data checks (checked_records), or with detrend
/// "mean" a copy without the record means (subtract_record_means copies columns that view a NumPy array: the caller's arrays stay
/// as they are).
std::shared_ptr<const Dataset> detrended(const Records& records, const tools::Config& c) {
  const std::string detrend = c.string_or("detrend", "none");
  std::shared_ptr<const Dataset> checked = checked_records(records, c);
  if (detrend == "none") return checked;
  if (detrend != "mean") c.fail("detrend", "must be \"none\" or \"mean\" (got \"" + detrend + "\")");
  auto copy = std::make_shared<Dataset>(*checked);
  subtract_record_means(*copy);
  return copy;
}

/// The refinement as the report states it: whether the likelihood was used and why, and what
/// to check (tools::Refinement::warnings).
nlohmann::ordered_json refinement_json(const tools::Refinement& f) {
  nlohmann::ordered_json j;
  j["used"] = f.result.has_value();
  j["sampling"] = f.adequacy.reason;
  if (!f.failure.empty()) j["failure"] = f.failure;  // the filter diverged: the moment fit stands
  if (!f.warnings.empty()) j["warnings"] = f.warnings;
  if (f.result) {
    j["log_likelihood"] = f.result->log_likelihood;
    j["bic"] = f.result->bic;
  }
  return j;
}

/// identify-vehs's fit (tools::identify_fit: the moment fit, refined by the likelihood when
/// asked or needed) of records in memory; the report holds the model file's report sections,
/// the units when given and "likelihood" (used, sampling adequacy, log L, BIC).
std::pair<ModelFile, std::string> identify_records(const Records& records, const std::string& options_json,
                                                   nb::object progress) {
  const tools::Config c = config_from_json(
      options_json, "vehs.identify", tools::identify_schema(),
      {"data", "output", "columns", "mat_variable", "dt", "sampling", "figures", "study"});
  (void)tools::identify_options(c);  // the options are checked before the GIL is released
  (void)tools::likelihood_settings(c);
  const nlohmann::ordered_json units = tools::units_block(c);
  const std::shared_ptr<const Dataset> data = detrended(records, c);
  std::optional<Dataset> ranged;
  tools::IdentifiedInMemory identified = run_released(std::move(progress), false, [&](const ProgressCallback& cb) {
    return tools::identify_in_memory(c, *data, cb, {}, ranged, "vehs.identify");
  });
  ModelFile f;
  f.sections = std::move(identified.sections);
  if (!units.empty()) f.sections["units"] = units;
  f.sections["likelihood"] = refinement_json(identified.fit.refinement);
  f.model = std::move(identified.fit.result.model);
  return {f, json_text(f.sections)};
}

/// identify-vehs's consistency study (the seed paper's Table 4): the `study` object and the
/// moment estimator's keys; the study's JSON as identify-vehs writes it, with its Table 4 text.
std::string identify_study(const std::string& options_json, nb::object progress) {
  const tools::Config c = config_from_json(
      options_json, "vehs.identify_study", tools::identify_schema(),
      {"output", "columns", "mat_variable", "dt", "sampling", "figures", "samples", "detrend", "units"});
  if (!c.has("study")) c.fail("study", "is missing (the truth and the grid of dt and samples)");
  identify::StudyOptions so = tools::study_options(c);
  const identify::StudyResult r = run_released(std::move(progress), false, [&](const ProgressCallback& cb) {
    so.progress = cb;
    return identify::run_study(so);
  });
  nlohmann::ordered_json j = tools::study_to_json(r);
  j["table"] = tools::study_text(r);
  return json_text(j);
}

}  // namespace

void bind_identify(nb::module_& m) {
  m.def("identify_study", &identify_study, nb::arg("options"), nb::arg("progress").none());
  m.def("identify", &identify_records, nb::arg("records"), nb::arg("options"), nb::arg("progress").none());
}

}  // namespace vehs::python
