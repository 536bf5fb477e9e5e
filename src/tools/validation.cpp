#include "tools/validation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include "tools/budget.hpp"
#include "tools/figures.hpp"
#include "tools/identify_tool.hpp"
#include "tools/likelihood_config.hpp"
#include "tools/measurement_config.hpp"
#include "vehs/core/detail/format.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/atomic_file.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/likelihood/free_run.hpp"

namespace vehs::tools {

const char* const kValidateHelp =
    "Free-run validation instead of a stochastic simulation: {\"data\": measurement file(s), "
    "\"columns\": {\"x\", \"u\", \"t\", \"traj\"}, \"dt\": for files without a time column, "
    "\"detrend\": \"mean\" | \"none\" (as in identify-vehs), \"segments\": [{\"name\", \"record\" "
    "(index, default 0), \"first\", \"last\" (sample range [first, last), default the whole "
    "record), \"phase\" (harmonic_forcing phase of that record; default the model's)}] (default: every record whole), \"skip\": samples left out of the RMSE at the start "
    "of each segment (default 50), \"input\": how the recorded input is applied between samples "
    "(default: the model file's estimator.input, else \"zoh\"), \"substeps\": RK4 substeps per "
    "interval (default 8), \"scale\" and \"unit\": for the printed table (e.g. 1000 and \"mV\"), "
    "\"output\": JSON of the scores (required), \"series\": CSV of measured and simulated x per "
    "segment (default beside output, _series.csv), \"figure\": true to draw measured vs simulated "
    "(gnuplot, beside output; \"figure_samples\": samples shown per segment, default 300)}. The "
    "model runs without noise from the measured initial state (x[0] and a one-sided difference "
    "for y) driven by the segment's input. The data must be sampled at the model's sampling "
    "interval (its \"sampling\".dt) when the model file states one. Only `model` and `validate` "
    "are used in this mode.";

namespace {

struct Segment {
  std::string name;
  std::size_t record = 0, first = 0, last = 0;
  std::optional<double> phase;  ///< harmonic_forcing phase of this record (else the model's)
};

std::string num(double v, int digits = 6) { return vehs::detail::format_number(v, digits); }

std::vector<Segment> parse_segments(const Config& v, const Dataset& data) {
  std::vector<Segment> out;
  if (!v.has("segments")) {
    for (std::size_t r = 0; r < data.records.size(); ++r)
      out.push_back({"record " + std::to_string(data.records[r].id), r, 0, data.records[r].size, std::nullopt});
    return out;
  }
  const auto& list = v.raw("segments");
  if (!list.is_array() || list.empty()) v.fail("segments", "must be a non-empty list of {name, record, first, last}");
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (!list[i].is_object()) v.fail("segments", "element " + std::to_string(i) + " must be an object");
    std::string path = v.where("segments").substr(v.file().size() + 3);
    path.pop_back();  // the closing quote of where()
    const Config s(list[i], v.file(), path + "[" + std::to_string(i) + "]");
    s.check_keys({"name", "record", "first", "last", "phase"});
    Segment seg;
    seg.record = static_cast<std::size_t>(s.integer_at_least("record", 0, 0));
    if (seg.record >= data.records.size())
      s.fail("record", "is " + std::to_string(seg.record) + " but the data have " + std::to_string(data.records.size()) + " record(s)");
    const std::size_t n = data.records[seg.record].size;
    seg.first = static_cast<std::size_t>(s.integer_at_least("first", 0, 0));
    seg.last = static_cast<std::size_t>(s.integer_at_least("last", 0, static_cast<long long>(n)));
    if (seg.last > n) s.fail("last", "is " + std::to_string(seg.last) + " but the record has " + std::to_string(n) + " samples");
    if (seg.last < seg.first + 3) s.fail("last", "must be at least first + 3");
    seg.name = s.string_or("name", "segment " + std::to_string(i));
    if (s.has("phase")) seg.phase = s.number("phase");
    out.push_back(seg);
  }
  return out;
}

std::string beside(const std::string& path, const std::string& suffix) {
  std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + suffix)).string();
}

/// gnuplot: per segment, measured and simulated x and their difference over `samples` samples
/// after the skipped transient (the series CSV's columns segment, k, t, u, measured, simulated).
std::string figure_script(const std::string& data_name, const std::vector<Segment>& segments,
                          const std::vector<likelihood::Validation>& results, const std::vector<double>& t_first,
                          const std::vector<double>& dt, std::size_t skip, std::size_t samples, double scale, const std::string& unit) {
  std::string body = "set datafile separator ','\nset key top right\nset xlabel 't'\nset ylabel 'x'\n";
  body += "set multiplot layout " + std::to_string(segments.size()) + ",1\n";
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const std::string sel = "($1 == " + std::to_string(i) + " && $2 >= " + std::to_string(skip) + " && $2 < " +
                            std::to_string(skip + samples) + " ? ";
    body += "set title " + gnuplot_quote(segments[i].name + ": RMSE " + num(results[i].rmse * scale, 3) + " " + unit) + "\n";
    body += "set xrange [" + num(t_first[i] + double(skip) * dt[i], 12) + ":" +
            num(t_first[i] + double(skip + samples) * dt[i], 12) + "]\n";
    body += "plot " + gnuplot_quote(data_name) + " using 3:" + sel + "$5 : 1/0) with lines lw 2 title 'measured', '' using 3:" + sel +
            "$6 : 1/0) with lines dt 2 title 'simulated', '' using 3:" + sel + "$5 - $6 : 1/0) with lines title 'error'\n";
  }
  return body + "unset multiplot\n";
}

}  // namespace

int run_validation(const Model& model, const Config& c, const AppOptions& app) {
  for (const char* key : {"output", "statistics", "drive", "summary"})
    if (c.has(key)) c.fail(key, "cannot be combined with 'validate' (the validation writes validate.output)");
  const Config v = c.object("validate", {"data", "columns", "dt", "detrend", "segments", "skip", "input", "substeps",
                                         "scale", "unit", "output", "series", "figure", "figure_samples"});
  const std::string output = v.path("output");
  const ReadOptions ro = read_options(v, model.uses_drive());  // the same columns and dt keys as identify
  Dataset data = read_measurements(v.path_list("data"), ro);
  const std::string detrend = v.string_or("detrend", "none");
  if (detrend == "mean")
    subtract_record_means(data);
  else if (detrend != "none")
    v.fail("detrend", "must be \"none\" or \"mean\"");
  const double model_dt = model.fit ? model.fit->sampling.dt : 0.0;
  for (const auto& r : data.records)
    if (model_dt > 0.0 && std::abs(r.dt - model_dt) > 1e-6 * model_dt)
      v.fail("data", r.source + " record " + std::to_string(r.id) + " is sampled at dt = " + num(r.dt) +
                         " but the model was fitted at dt = " + num(model_dt) + " (sampling mismatch)");
  const auto segments = parse_segments(v, data);
  likelihood::FreeRunOptions fo;
  fo.input = model.fit ? model.fit->input : InputInterpolation::ZeroOrderHold;
  if (v.has("input")) fo.input = enum_from_string(kInputInterpolationNames, v.string("input"), v.where("input"));
  fo.substeps = v.int_at_least("substeps", 1, 8);
  if (fo.substeps > 1000) v.fail("substeps", "must be <= 1000");
  const auto skip = static_cast<std::size_t>(v.integer_at_least("skip", 0, 50));
  const double scale = v.positive_or("scale", 1.0);
  const std::string unit = v.string_or("unit", "");
  const bool figure = v.boolean_or("figure", false);
  const auto figure_samples = static_cast<std::size_t>(v.integer_at_least("figure_samples", 10, 300));
  const std::string series_path = v.path_or("series", beside(output, "_series.csv"));
  double samples = 0.0;  // free-run samples of all segments: the measured and simulated series in
  for (const auto& seg : segments) samples += static_cast<double>(seg.last - seg.first);  // memory and the CSV
  const std::string sizes = "(" + num(static_cast<double>(segments.size())) + " segments, " + num(samples) + " samples)";
  check_budget(c, {{Resource::Steps, samples * fo.substeps, "integration steps " + sizes, "validate fewer or shorter segments"},
                   {Resource::Memory, samples * 120.0, sizes, "validate fewer or shorter segments"},
                   {Resource::Output, samples * 100.0, sizes, "validate fewer or shorter segments"}});

  if (model.uses_drive()) check_input_interpolation(fo.input, data, true, v.where("input"));
  nlohmann::ordered_json j;
  j["input"] = enum_to_string(kInputInterpolationNames, fo.input);
  j["substeps"] = fo.substeps;
  j["skip"] = skip;
  j["segments"] = nlohmann::ordered_json::array();
  std::ostringstream csv;
  csv.precision(10);
  csv << "segment,k,t,u,measured,simulated\n";  // segment: index into "segments" of the JSON
  std::vector<likelihood::Validation> results;
  std::vector<double> t_first, dts;  // time of each segment's first sample, its sampling interval
  for (const auto& seg : segments) {
    const Record& rec = data.records[seg.record];
    if (seg.last - seg.first <= skip)
      v.fail("skip", "leaves no samples of segment '" + seg.name + "' (" + std::to_string(seg.last - seg.first) + " samples)");
    const double* x = data.x_of(rec);
    const std::vector<double> xs(x + seg.first, x + seg.last);
    std::vector<double> us;
    if (model.uses_drive()) us.assign(data.u_of(rec) + seg.first, data.u_of(rec) + seg.last);
    fo.t0 = rec.t0 + static_cast<double>(seg.first) * rec.dt;
    fo.phase = seg.phase;
    t_first.push_back(fo.t0);
    dts.push_back(rec.dt);
    likelihood::Validation val;
    try {
      val = likelihood::validate_free_run(model, xs, us, rec.dt, skip, fo);
    } catch (const Error& e) {
      throw Error(v.where("segments") + ": segment '" + seg.name + "': " + e.what());
    }
    if (!std::isfinite(val.rmse)) throw Error(v.where("segments") + ": segment '" + seg.name + "': the free run is not finite");
    nlohmann::ordered_json s;
    s["name"] = seg.name;
    s["source"] = rec.source;
    s["record"] = rec.id;
    s["first"] = seg.first;
    s["last"] = seg.last;
    s["rmse"] = val.rmse;
    s["measured_rms"] = val.measured_rms;
    s["relative_rmse"] = val.rmse / val.measured_rms;
    s["initial_state"] = {{"x", val.initial.x}, {"y", val.initial.y}};
    j["segments"].push_back(s);
    for (std::size_t k = 0; k < val.measured.size(); ++k)
      csv << results.size() << ',' << k << ',' << fo.t0 + double(k) * rec.dt << ',' << (us.empty() ? 0.0 : us[k]) << ','
          << val.measured[k] << ',' << val.simulated[k] << '\n';
    results.push_back(std::move(val));
  }
  write_file_atomically(series_path, csv.str());
  j["series"] = series_path;
  if (figure) {
    const std::filesystem::path dir = std::filesystem::path(output).parent_path();
    const std::string body = figure_script(std::filesystem::path(series_path).filename().string(), segments, results,
                                           t_first, dts, skip, figure_samples, scale, unit);
    const std::string fig = render_figure(dir.empty() ? "." : dir.string(), std::filesystem::path(output).stem().string(), body,
                                          "svg", 1000, 300 * static_cast<int>(segments.size()));
    if (!fig.empty()) j["figure"] = fig;
  }
  write_json_atomically(output, j);
  if (!app.quiet) {
    std::printf("%-28s %10s %10s %12s %12s\n", "segment", "first", "last", ("RMSE " + unit).c_str(), ("rms " + unit).c_str());
    for (std::size_t i = 0; i < segments.size(); ++i)
      std::printf("%-28s %10zu %10zu %12.4g %12.4g\n", segments[i].name.c_str(), segments[i].first, segments[i].last,
                  results[i].rmse * scale, results[i].measured_rms * scale);
    std::fprintf(stderr, "simulate-vehs: validation written to %s and %s\n", output.c_str(), series_path.c_str());
  }
  return 0;
}

}  // namespace vehs::tools
