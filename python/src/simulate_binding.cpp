// vehs.simulate and vehs.monte_carlo: the simulator with simulate-vehs's keys, records handed to
// NumPy without a copy, Ctrl-C stopping every thread cleanly.
#include <nanobind/stl/optional.h>
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

using Drive = std::vector<InColumn>;

/// simulate-vehs's job from keyword arguments with the model given as an object and the drive
/// (optional) as arrays sampled at dt; the file keys (output, summary, drive) are Python's
/// business: the keys are checked first, then `output` is set to a placeholder when records are
/// wanted (nothing is written), and `statistics` needs no output.
tools::SimulateJob job_from_options(const ModelFile& model, const std::string& options_json, const char* where,
                                    bool records, const std::optional<Drive>& drive) {
  (void)config_from_json(options_json, where, tools::simulate_schema(), {"output", "summary", "drive"});
  nlohmann::json j = nlohmann::json::parse(options_json);
  j["model"] = nlohmann::json(model_to_json(model.model));
  if (records) j["output"] = "records.npy";
  if (j.contains("statistics") && j["statistics"].is_object() && !j["statistics"].contains("output"))
    j["statistics"]["output"] = "";
  const tools::Config c = config_from_json(j.dump(), where, tools::simulate_schema(), {"summary", "drive"});
  std::vector<std::vector<double>> series;
  if (drive)
    for (const InColumn& u : *drive) series.emplace_back(u.data(), u.data() + u.shape(0));
  tools::SimulateJob job = tools::simulate_job_from_config(c, drive ? &series : nullptr);
  job.model = model.model;  // the typed model itself (no JSON round trip)
  job.model_sections = model.sections;  // units and harvester, for the mean power in W
  if (job.harvester.empty() && model.sections.contains("harvester")) job.harvester = model.sections["harvester"];
  return job;
}

/// The statistics as simulate-vehs writes them, plus each record's mean of every moment
/// ("record_means", record order) and its batch means ("batch_means", record by record, with
/// "batch_lengths") so that blocks of records merge exactly (vehs.dask.merge_statistics).
std::string statistics_text(const tools::SimulateJob& job, const tools::SimulateRun& run) {
  const sim::MonteCarloStatistics& st = run.statistics;
  nlohmann::ordered_json j = tools::statistics_to_json(st);
  j["mean_power"] = run.power;
  nlohmann::ordered_json means = nlohmann::ordered_json::object();
  for (std::size_t k = 0; k < st.moments.size(); ++k) means[st.moments[k].first] = st.record_means[k];
  j["record_means"] = means;
  nlohmann::ordered_json batches = nlohmann::ordered_json::object();
  for (std::size_t k = 0; k < st.moments.size(); ++k) batches[st.moments[k].first] = st.batch_means[k];
  j["batch_means"] = batches;
  j["batch_lengths"] = st.batch_lengths;
  j["samples_per_record"] = st.samples_per_record;
  j["min_records_for_spread"] = job.statistics.min_records_for_spread;
  if (st.has_histograms)
    j["counts"] = {{"px", st.px.counts}, {"py", st.py.counts}, {"pxy", st.pxy.counts},
                   {"outside", {st.px.outside, st.py.outside, st.pxy.outside}},
                   {"total", {st.px.total, st.py.total, st.pxy.total}}};
  return json_text(j);
}

tools::SimulateRun run_job(const tools::SimulateJob& job, nb::object progress) {
  return run_released(std::move(progress), true,
                      [&](const ProgressCallback& cb) { return tools::simulate_job(job, cb); });
}

/// The records, and with `statistics` also their statistics (one run, as simulate-vehs with
/// both 'output' and 'statistics'; "" without).
std::pair<Records, std::string> simulate_records(const ModelFile& model, const std::string& options_json,
                                                 nb::object progress, const std::optional<Drive>& drive) {
  const tools::SimulateJob job = job_from_options(model, options_json, "vehs.simulate", true, drive);
  tools::SimulateRun run = run_job(job, std::move(progress));
  Records out;
  *out.data = std::move(run.data);  // the simulator's memory, handed over
  return {out, job.with_statistics ? statistics_text(job, run) : std::string()};
}

std::string monte_carlo(const ModelFile& model, const std::string& options_json, nb::object progress,
                        const std::optional<Drive>& drive) {
  const tools::SimulateJob job = job_from_options(model, options_json, "vehs.monte_carlo", false, drive);
  if (!job.with_statistics) throw Error("vehs.monte_carlo: give 'statistics' (an object, {} for the defaults)");
  return statistics_text(job, run_job(job, std::move(progress)));
}

}  // namespace

void bind_simulate(nb::module_& m) {
  m.def("simulate", &simulate_records, nb::arg("model"), nb::arg("options"), nb::arg("progress").none(),
        nb::arg("drive").none() = nb::none());
  m.def("monte_carlo", &monte_carlo, nb::arg("model"), nb::arg("options"), nb::arg("progress").none(),
        nb::arg("drive").none() = nb::none());
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
