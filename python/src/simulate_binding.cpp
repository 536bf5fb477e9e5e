// vehs.simulate and vehs.monte_carlo: the simulator with simulate-vehs's keys, records handed to
// NumPy without a copy, Ctrl-C stopping every thread cleanly.
#include <nanobind/stl/string.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/vector.h>

#include "bindings.hpp"
#include "bridge.hpp"
#include "records.hpp"
#include "tools/simulate_tool.hpp"
#include "tools/statistics_file.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/statistics.hpp"

namespace vehs::python {

namespace {

/// simulate-vehs's job from keyword arguments with the model given as an object; the file keys
/// (output, summary, drive) are Python's business: the keys are checked first, then `output` is
/// set to a placeholder when records are wanted (nothing is written), and `statistics` needs no
/// output.
tools::SimulateJob job_from_options(const ModelFile& model, const std::string& options_json, const char* where,
                                    bool records) {
  (void)config_from_json(options_json, where, tools::simulate_schema(), {"output", "summary", "drive"});
  nlohmann::json j = nlohmann::json::parse(options_json);
  j["model"] = nlohmann::json(model_to_json(model.model));
  if (records) j["output"] = "records.npy";
  if (j.contains("statistics") && j["statistics"].is_object() && !j["statistics"].contains("output"))
    j["statistics"]["output"] = "";
  const tools::Config c = config_from_json(j.dump(), where, tools::simulate_schema(), {"summary", "drive"});
  tools::SimulateJob job = tools::simulate_job_from_config(c);
  job.model = model.model;  // the typed model itself (no JSON round trip)
  return job;
}

Records simulate_records(const ModelFile& model, const std::string& options_json, nb::object progress) {
  tools::SimulateJob job = job_from_options(model, options_json, "vehs.simulate", true);
  Records out;
  run_released(std::move(progress), true, [&](const ProgressCallback& cb) {
    job.options.progress = cb;
    sim::simulate(job.model, job.options, *out.data);
  });
  return out;
}

/// The statistics as simulate-vehs writes them, plus each record's mean of every moment
/// ("record_means", record order) so that blocks of records merge exactly (merge_moments).
std::string monte_carlo(const ModelFile& model, const std::string& options_json, nb::object progress) {
  tools::SimulateJob job = job_from_options(model, options_json, "vehs.monte_carlo", false);
  if (!job.with_statistics) throw Error("vehs.monte_carlo: give 'statistics' (an object, {} for the defaults)");
  const sim::MonteCarloStatistics st = run_released(std::move(progress), true, [&](const ProgressCallback& cb) {
    job.options.progress = cb;
    return sim::simulate_statistics(job.model, job.options, job.statistics);
  });
  nlohmann::ordered_json j = tools::statistics_to_json(st);
  nlohmann::ordered_json means = nlohmann::ordered_json::object();
  for (std::size_t k = 0; k < st.moments.size(); ++k) means[st.moments[k].first] = st.record_means[k];
  j["record_means"] = means;
  j["samples_per_record"] = st.samples_per_record;
  j["min_records_for_spread"] = job.statistics.min_records_for_spread;
  if (st.has_histograms)
    j["counts"] = {{"px", st.px.counts}, {"py", st.py.counts}, {"pxy", st.pxy.counts},
                   {"outside", {st.px.outside, st.py.outside, st.pxy.outside}},
                   {"total", {st.px.total, st.py.total, st.pxy.total}}};
  return json_text(j);
}

}  // namespace

void bind_simulate(nb::module_& m) {
  m.def("simulate", &simulate_records, nb::arg("model"), nb::arg("options"), nb::arg("progress").none());
  m.def("monte_carlo", &monte_carlo, nb::arg("model"), nb::arg("options"), nb::arg("progress").none());
  m.def("combine_independent",
        [](const std::vector<double>& values, const std::vector<double>& weights) {
          std::vector<Estimate> groups;
          for (double v : values) groups.push_back({v, 0.0});
          const Estimate e = combine_independent(groups, weights);
          return std::make_pair(e.value, e.stderr_);
        },
        nb::arg("values"), nb::arg("weights"),
        "The mean of independent groups and its standard error from their spread (the Monte Carlo merge).");
}

}  // namespace vehs::python
