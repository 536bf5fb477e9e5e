// vehs.diagnose: diagnose-vehs's keys, records read in place, the report folder and its history
// written as the CLI writes them when a folder is given.
#include <filesystem>

#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>

#include "bindings.hpp"
#include "bridge.hpp"
#include "records.hpp"
#include "tools/diagnose_tool.hpp"
#include "tools/diagnosis_file.hpp"
#include "tools/diagnosis_report.hpp"
#include "tools/history.hpp"
#include "tools/html_report.hpp"

namespace vehs::python {

namespace {

/// Writes the HTML report (and appends to the folder's history.json); returns its path.
std::string write_report(const std::string& folder, const std::string& label, const ModelFile& model,
                         const Dataset& data, const diagnose::Result& r) {
  const std::string history = (std::filesystem::path(folder) / "history.json").string();
  const auto entries =
      tools::append_history(history, tools::history_entry(model.model, "(python)", label, data, r, model.sections));
  tools::Report report(folder, "vehs.diagnose: " + label);
  tools::add_diagnosis_to_report(report, r, label, entries, tools::data_fingerprint(data), nlohmann::json::object(), {},
                                 &model.model, &data);
  return report.write_html();
}

std::pair<std::string, std::string> diagnose_records(const ModelFile& model, const Records& records,
                                                     const std::string& options_json, const std::string& report,
                                                     const std::string& label, nb::object progress) {
  const tools::Config c = config_from_json(options_json, "vehs.diagnose", tools::diagnose_schema(),
                                           {"model", "data", "output", "report", "history", "label", "columns",
                                            "detrend"});
  diagnose::Options o = tools::diagnose_options(c);
  validate_model(model.model, label);
  require(!model.model.drift.empty(), label + ": the model has no drift terms");
  require(!model.model.diffusion.empty(), label + ": the model has no diffusion terms");
  if (!report.empty()) tools::read_history((std::filesystem::path(report) / "history.json").string());
  const std::shared_ptr<const Dataset> data = checked_records(records, c);
  const diagnose::Result r = run_released(std::move(progress), false, [&](const ProgressCallback& cb) {
    o.progress = cb;
    return diagnose::diagnose(model.model, *data, o);
  });
  nlohmann::ordered_json j = tools::diagnosis_to_json(r, &model.model);
  j["label"] = label;
  const std::string html = report.empty() ? "" : write_report(report, label, model, *data, r);
  j["report"] = html;
  return {json_text(j), html};
}

}  // namespace

void bind_diagnose(nb::module_& m) {
  m.def("diagnose", &diagnose_records, nb::arg("model"), nb::arg("records"), nb::arg("options"),
        nb::arg("report"), nb::arg("label"), nb::arg("progress").none());
}

}  // namespace vehs::python
