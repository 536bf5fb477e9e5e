// vehs.identify: identify-vehs's estimator keys, records read in place.
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>

#include "bindings.hpp"
#include "bridge.hpp"
#include "records.hpp"
#include "tools/identify_file.hpp"
#include "tools/identify_tool.hpp"

namespace vehs::python {

namespace {

/// The records to work on: `records` itself, or with detrend "mean" a copy without the record
/// means (the caller's arrays stay as they are).
std::shared_ptr<const Dataset> detrended(const Records& records, const tools::Config& c) {
  const std::string detrend = c.string_or("detrend", "none");
  if (detrend == "none") return records.data;
  if (detrend != "mean") c.fail("detrend", "must be \"none\" or \"mean\" (got \"" + detrend + "\")");
  auto copy = std::make_shared<Dataset>(*records.data);
  subtract_record_means(*copy);
  return copy;
}

std::pair<ModelFile, std::string> identify_records(const Records& records, const std::string& options_json,
                                                   nb::object progress) {
  const tools::Config c = config_from_json(options_json, "vehs.identify", tools::identify_schema(),
                                           {"data", "output", "columns", "dt", "study"});
  identify::Options o = tools::identify_options(c);
  const std::shared_ptr<const Dataset> data = detrended(records, c);
  identify::Result r = run_released(std::move(progress), false, [&](const ProgressCallback& cb) {
    o.progress = cb;
    return identify::identify(*data, o);
  });
  validate_model(r.model, "vehs.identify");
  ModelFile f;
  f.sections = tools::identify_report_sections(r);
  f.model = std::move(r.model);
  return {f, json_text(f.sections)};
}

}  // namespace

void bind_identify(nb::module_& m) {
  m.def("identify", &identify_records, nb::arg("records"), nb::arg("options"), nb::arg("progress").none());
}

}  // namespace vehs::python
