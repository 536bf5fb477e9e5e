// vehs.identify: identify-vehs's estimator keys, records read in place.
#include <optional>

#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "bindings.hpp"
#include "bridge.hpp"
#include "records.hpp"
#include "tools/identify_tool.hpp"
#include "tools/data_checks.hpp"
#include "tools/likelihood_config.hpp"
#include "tools/measurement_config.hpp"
#include "tools/study_output.hpp"

namespace vehs::python {

namespace {

/// vehs.FitOptions: identify-vehs's keys read once, with the CLI's key table and messages, into the
/// fit's typed options (vehs::FitOptions); the common ones are properties a user sets by name. The
/// keys the call acts on itself (units, detrend, samples) stay with the config.
struct PyFitOptions {
  tools::Config config;
  FitOptions options;
};

PyFitOptions fit_options_from_json(const std::string& options_json) {
  tools::Config c = config_from_json(options_json, "vehs.identify", tools::identify_schema(),
                                     {"data", "output", "columns", "mat_variable", "dt", "sampling", "figures", "study"});
  FitOptions f = tools::fit_options(c);
  (void)tools::units_block(c);
  (void)c.string_or("detrend", "none");
  return {std::move(c), std::move(f)};
}

/// The records to work on: `records` after the data checks (checked_records), or with detrend
/// "mean" a copy without the record means (subtract_record_means copies columns that view a NumPy array: the caller's arrays stay
/// as they are).
std::shared_ptr<const Dataset> detrended(const Records& records, const PyFitOptions& o) {
  const std::string detrend = o.config.string_or("detrend", "none");
  std::shared_ptr<const Dataset> checked = checked_records(records, o.options.checks);
  if (detrend == "none") return checked;
  if (detrend != "mean") o.config.fail("detrend", "must be \"none\" or \"mean\" (got \"" + detrend + "\")");
  auto copy = std::make_shared<Dataset>(*checked);
  subtract_record_means(*copy);
  return copy;
}

/// The refinement as the report states it: whether the likelihood was used and why, and what
/// to check (vehs::Refinement::warnings).
nlohmann::ordered_json refinement_json(const Refinement& f) {
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

/// identify-vehs's fit (vehs::fit through tools::identify_in_memory) of records in memory under
/// typed options; the report holds the model file's report sections, the units when given and
/// "likelihood" (used, sampling adequacy, log L, BIC).
std::pair<ModelFile, std::string> identify_records(const Records& records, const PyFitOptions& options,
                                                   nb::object progress) {
  const nlohmann::ordered_json units = tools::units_block(options.config);
  const std::shared_ptr<const Dataset> data = detrended(records, options);
  std::optional<Dataset> ranged;
  tools::IdentifiedInMemory identified = run_released(std::move(progress), false, [&](const ProgressCallback& cb) {
    return tools::identify_in_memory(options.config, options.options, *data, cb, {}, ranged, "vehs.identify");
  });
  ModelFile f;
  f.sections = std::move(identified.sections);
  if (!units.empty()) f.sections["units"] = units;
  f.sections["likelihood"] = refinement_json(identified.fit.refinement);
  f.model = std::move(identified.fit.result.model);
  return {f, json_text(f.sections)};
}

template <class Enum, std::size_t N>
void set_enum(Enum& field, const EnumNames<Enum, N>& names, const std::string& value, const char* property) {
  field = enum_from_string(names, value, std::string("vehs.FitOptions.") + property);
}

inline constexpr EnumNames<LikelihoodUse, 3> kLikelihoodUseNames{
    {{LikelihoodUse::Auto, "auto"}, {LikelihoodUse::Always, "always"}, {LikelihoodUse::Never, "never"}}};

std::vector<std::string> term_names(const std::vector<Term>& library) {
  std::vector<std::string> out;
  for (const Term& t : library) out.push_back(t.name());
  return out;
}

std::vector<Term> parse_terms(const std::vector<std::string>& names) {
  std::vector<Term> out;
  for (const std::string& n : names) out.push_back(Term::parse(n));
  return out;
}

std::string fit_options_repr(const PyFitOptions& p) {
  const FitOptions& o = p.options;
  std::string effects;
  for (const Effect& e : o.moment.effects) effects += (effects.empty() ? "'" : ", '") + e.name() + "'";
  for (const UserEffect& e : o.moment.user_effects) effects += (effects.empty() ? "'" : ", '") + e.name + "'";
  auto list = [](const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& t : v) s += (s.empty() ? "'" : ", '") + t + "'";
    return "[" + s + "]";
  };
  return "FitOptions(estimator='" + enum_to_string(kEstimatorNames, o.moment.estimator) + "', likelihood_use='" +
         enum_to_string(kLikelihoodUseNames, o.likelihood.use) + "', drift_library=" +
         (o.libraries_given.drift ? list(term_names(o.moment.drift_library)) : std::string("default")) +
         ", diffusion_library=" +
         (o.libraries_given.diffusion ? list(term_names(o.moment.diffusion_library)) : std::string("default")) +
         ", effects=[" + effects + "], glitches='" + enum_to_string(kCheckRuleNames, o.checks.glitches) +
         "', flat_stretches='" + enum_to_string(kCheckRuleNames, o.checks.flat_stretches) + "')";
}

void bind_fit_options(nb::module_& m) {
  nb::class_<PyFitOptions>(m, "FitOptions",
                           "The fit's typed options (vehs::FitOptions), read from identify-vehs's keys once.")
      .def("__init__", [](PyFitOptions* self, const std::string& json) { new (self) PyFitOptions(fit_options_from_json(json)); },
           nb::arg("options_json"))
      .def_prop_rw(
          "estimator", [](const PyFitOptions& p) { return enum_to_string(kEstimatorNames, p.options.moment.estimator); },
          [](PyFitOptions& p, const std::string& v) { set_enum(p.options.moment.estimator, kEstimatorNames, v, "estimator"); })
      .def_prop_rw(
          "likelihood_use", [](const PyFitOptions& p) { return enum_to_string(kLikelihoodUseNames, p.options.likelihood.use); },
          [](PyFitOptions& p, const std::string& v) { set_enum(p.options.likelihood.use, kLikelihoodUseNames, v, "likelihood_use"); },
          "When the likelihood refines the moment fit: 'auto', 'always' or 'never'.")
      .def_prop_rw(
          "likelihood_starts", [](const PyFitOptions& p) { return p.options.likelihood_starts; },
          [](PyFitOptions& p, bool v) { p.options.likelihood_starts = v; },
          "Under estimator 'auto', start the likelihood from every moment fit and keep the highest.")
      .def_prop_rw(
          "drift_library", [](const PyFitOptions& p) { return term_names(p.options.moment.drift_library); },
          [](PyFitOptions& p, const std::vector<std::string>& v) {
            p.options.moment.drift_library = parse_terms(v);
            p.options.libraries_given.drift = true;
          })
      .def_prop_rw(
          "diffusion_library", [](const PyFitOptions& p) { return term_names(p.options.moment.diffusion_library); },
          [](PyFitOptions& p, const std::vector<std::string>& v) {
            p.options.moment.diffusion_library = parse_terms(v);
            p.options.libraries_given.diffusion = true;
          })
      .def_prop_ro("effects",
                   [](const PyFitOptions& p) {
                     std::vector<std::string> out;
                     for (const Effect& e : p.options.moment.effects) out.push_back(e.name());
                     for (const UserEffect& e : p.options.moment.user_effects) out.push_back(e.name);
                     return out;
                   },
                   "The requested effects' names: the catalogue's, then the user's own.")
      .def_prop_rw(
          "glitches", [](const PyFitOptions& p) { return enum_to_string(kCheckRuleNames, p.options.checks.glitches); },
          [](PyFitOptions& p, const std::string& v) { set_enum(p.options.checks.glitches, kCheckRuleNames, v, "glitches"); })
      .def_prop_rw(
          "flat_stretches",
          [](const PyFitOptions& p) { return enum_to_string(kCheckRuleNames, p.options.checks.flat_stretches); },
          [](PyFitOptions& p, const std::string& v) {
            set_enum(p.options.checks.flat_stretches, kCheckRuleNames, v, "flat_stretches");
          })
      .def("__repr__", &fit_options_repr);
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
  bind_fit_options(m);
  m.def("identify_study", &identify_study, nb::arg("options"), nb::arg("progress").none());
  m.def("identify", &identify_records, nb::arg("records"), nb::arg("options"), nb::arg("progress").none());
}

}  // namespace vehs::python
