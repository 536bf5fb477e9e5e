#include "tools/simulate_tool.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>

#include "tools/budget.hpp"
#include "tools/power.hpp"
#include "tools/power_estimate.hpp"
#include "tools/statistics_file.hpp"
#include "tools/validation.hpp"
#include "vehs/core/detail/format.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/parallel.hpp"
#include "vehs/io/atomic_file.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/likelihood/signals.hpp"

namespace vehs::tools {

using namespace vehs::sim;

const ConfigSchema& simulate_schema() {
  static const ConfigSchema schema{
      "simulate-vehs",
      "Simulates records of dX = Y dt, dY = b2 dt + sqrt(a22) dB (plus the model's named effects) "
      "as a sensor samples them, writes them as a measurement file, and optionally Monte Carlo "
      "statistics (moments with standard errors, histograms on the fpk-stationary grid).",
      {
          {"model", "object|path",
           "The model (docs/model-file.md): an inline object or the path of a model file. Term-like "
           "effects become drift/diffusion terms; impact_stop, harmonic_forcing, "
           "electromechanical_coupling and colored_noise are simulated as dynamic effects.",
           "", false},
          {"trajectories", "integer >= 1", "Number of independent records.", "100", false},
          {"duration", "number > 0",
           "Length of each record in time units: samples = duration / dt recorded values at "
           "t = 0, dt, ..., duration - dt (the paper: duration 100, dt 0.001 gives 10^5 samples). "
           "Must be a whole number of dt.",
           "100", false},
          {"dt", "number > 0", "Recorded sampling interval.", "0.001", false},
          {"substeps", "integer >= 1",
           "Internal integration steps per recorded interval (h = dt / substeps): >1 emulates a "
           "sensor sampling a continuous process.",
           "1", false},
          {"scheme", "string",
           "Integration scheme: euler_maruyama (strong order 1 here), rk4_euler (the paper's Eq. 30: "
           "RK4 drift + Euler noise), baoab (splitting with an exact Ornstein-Uhlenbeck step, small "
           "long-run bias), taylor15 (Kloeden-Platen strong order 1.5; the most accurate per step).",
           "taylor15", false},
          {"seed", "integer >= 0",
           "Seed of the counter-based generator (Philox-4x32-10). Records are identical whatever "
           "--threads is.",
           "1", false},
          {"x0", "{\"uniform\": [a, b]} | [x per record] | number",
           "Initial displacement: uniform in [a, b] (the paper: [-1.5, 1.5]), one value per record, "
           "or one value for all.",
           "{\"uniform\": [-1.5, 1.5]}", false},
          {"y0", "number | {\"uniform\": [a, b]} | [y per record]", "Initial velocity.", "0", false},
          {"burn_in", "number >= 0",
           "Time simulated before t = 0 and not recorded (lets records forget x0, y0). Not with a "
           "drive.",
           "0", false},
          {"sensor_noise", "number >= 0",
           "Standard deviation of white Gaussian noise added to the recorded x (measurement noise; "
           "the dynamics are not affected).",
           "0", false},
          {"record_velocity", "bool", "Also write the true velocity as column y.", "true", false},
          {"drive", "{\"path\": file, \"column\": name, \"t_column\": name}",
           "Recorded drive u for models with a 'u' term, read from a measurement file (CSV or .npy; "
           "column defaults to \"u\", t_column to \"t\" and may be absent). It must be sampled at dt "
           "and is held constant over each interval (zero-order hold). One record is shared by all "
           "trajectories; otherwise the file needs one record per trajectory.",
           "", true},
          {"output", "path",
           "Measurement file to write (columns traj, t, x[, y][, u]); .npy writes NumPy binary, "
           "anything else CSV (a .mat, .npz, .h5, .hdf5, .xlsx, .xls or .parquet name is refused). "
           "Optional when 'statistics' is given.",
           "", true},
          {"statistics", "object",
           "Monte Carlo statistics, accumulated while simulating (no records kept unless 'output' "
           "is given): {\"output\": JSON path (required), \"discard\": time left out at the start "
           "of each record (default 0), \"grid\": {\"x\": [min, max, n], \"y\": [min, max, n]} for "
           "histograms on fpk-stationary's cell-centred grid, \"px\", \"py\", \"pxy\": CSV paths "
           "(default: beside the JSON), \"batches\": batches per record for batch-means errors "
           "(default 32), \"parameters\": true to add the fitted model's parameter errors to the "
           "power's standard error (delta method; 2 more runs per parameter)}. The JSON has E[X], "
           "E[Y], E[X^2], E[Y^2], E[XY], E[X^4] (and E[V^2] with electromechanical coupling) and "
           "\"stderr\" for each: from the spread of independent records when there are >= 16, else "
           "from batch means; and \"mean_power\" (W with 'harvester', with its standard error). "
           "Works with any drive (zero-order hold or the model's interpolated input).",
           "", true},
          harvester_key(),
          {"first_record", "integer >= 0",
           "Id of the first record (traj column and random stream): runs with first_record = 0 and "
           "= 100 give the same records as one run of 200.",
           "0", false},
          {"divergence_bound", "number > 0",
           "A record whose |x| or |y| exceeds this (or becomes non-finite) stops the run with an "
           "error naming it; x0 and y0 must lie within it.",
           "1e8", false},
          {"allow_unconfined", "bool",
           "Simulate even when the potential does not confine (leading power of the restoring "
           "force even or with a positive coefficient, and no impact stop).",
           "false", false},
          {"summary", "path", "JSON report of the run (sizes, scheme, time, steps per second).", "",
           true},
          {"validate", "object", kValidateHelp, "", true},
          force_key(),
          {"record_phases", "[phase per trajectory]",
           "harmonic_forcing with one phase per record (records started at unrelated times; "
           "amplitude and omega shared): one phase per trajectory. Default: the model file's "
           "likelihood.record_phases when it has one per trajectory, else the model's phase for "
           "all. Not with 'statistics'.",
           "", true},
      },
      "Example (the seed paper's data): {\"model\": \"data/sim/paper_model.json\", \"trajectories\": "
      "100, \"duration\": 100, \"dt\": 0.001, \"scheme\": \"rk4_euler\", \"x0\": {\"uniform\": "
      "[-1.5, 1.5]}, \"output\": \"paper.npy\"}. See data/sim/README.md."};
  return schema;
}

namespace {

std::string num(double v) { return vehs::detail::format_number(v, 10); }

// {"uniform": [a, b]}
bool parse_uniform(const Config& c, const std::string& key, double& lo, double& hi) {
  const auto& v = c.raw(key);
  if (!v.is_object()) return false;
  if (v.size() != 1 || !v.contains("uniform"))
    c.fail(key, "must be {\"uniform\": [a, b]}, a number or a list of numbers");
  const auto& u = v["uniform"];
  if (!u.is_array() || u.size() != 2 || !u[0].is_number() || !u[1].is_number())
    c.fail(key, "uniform must be [a, b] with numbers a <= b");
  lo = u[0].get<double>();
  hi = u[1].get<double>();
  if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi) c.fail(key, "uniform must be [a, b] with finite a <= b");
  return true;
}

std::vector<double> number_list(const Config& c, const std::string& key, std::size_t expected) {
  const auto& v = c.raw(key);
  std::vector<double> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!v[i].is_number()) c.fail(key, "element " + std::to_string(i) + " is not a number");
    out.push_back(v[i].get<double>());
    if (!std::isfinite(out.back())) c.fail(key, "element " + std::to_string(i) + " is not finite");
  }
  if (out.size() != expected)
    c.fail(key, "has " + std::to_string(out.size()) + " values but there are " + std::to_string(expected) +
                    " trajectories (one value per record)");
  return out;
}

std::string beside(const std::string& json_path, const std::string& suffix) {
  const auto dot = json_path.find_last_of('.');
  const auto slash = json_path.find_last_of('/');
  const std::string stem = dot != std::string::npos && (slash == std::string::npos || dot > slash)
                               ? json_path.substr(0, dot)
                               : json_path;
  return stem + suffix;
}

void read_grid_axis(const Config& g, const std::string& axis, double& lo, double& hi, std::size_t& n) {
  const auto& v = g.raw(axis);
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    g.fail(axis, "must be [min, max, n]");
  lo = v[0].get<double>();
  hi = v[1].get<double>();
  const double nd = v[2].get<double>();
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi)) g.fail(axis, "needs finite min < max");
  if (!(nd >= 1) || nd != std::floor(nd) || nd > 1e5) g.fail(axis, "n must be a whole number in [1, 1e5]");
  n = static_cast<std::size_t>(nd);
}

/// The drive series (from `name`) as the options' drive: one shared, or one per trajectory.
void assign_drive(const Config& c, const std::string& name, std::vector<std::vector<double>> series,
                  SimulationOptions& o) {
  if (series.size() == 1) {
    o.drive = std::move(series[0]);
  } else if (series.size() == static_cast<std::size_t>(o.records)) {
    o.drive_per_record = std::move(series);
  } else {
    c.fail("drive", name + " has " + std::to_string(series.size()) +
                        " records: give one (shared) or one per trajectory (" + std::to_string(o.records) + ")");
  }
}

}  // namespace

namespace {

/// Steps, memory and output of a simulation job (docs/config.md, Budgets).
std::vector<Estimate> simulate_estimates(const SimulateJob& job) {
  const SimulationOptions& o = job.options;
  const double records = o.records, samples = static_cast<double>(o.samples);
  const double burn = std::round(o.burn_in / o.dt);
  const bool driven = !o.drive.empty() || !o.drive_per_record.empty();
  const double columns = 1.0 + (o.record_y ? 1.0 : 0.0) + (driven ? 1.0 : 0.0);
  const double values = records * samples * columns;  // the records, kept in memory to be written
  const bool keep = !job.output.empty() || !job.with_statistics;
  double memory = records * 24.0 + (keep ? values * 8.0 : 0.0);  // (initial states per record)
  double output = 0.0;
  if (!job.output.empty())
    output += std::filesystem::path(job.output).extension() == ".npy" ? records * samples * (columns + 2.0) * 8.0
                                                                       : records * samples * (12.0 + 20.0 * columns);
  if (job.with_statistics) {
    const StatisticsOptions& st = job.statistics;
    memory += records * 7.0 * static_cast<double>(st.batches) * 8.0;  // batch sums per record
    if (st.histograms) {
      const double cells = static_cast<double>(st.nx) * static_cast<double>(st.ny);
      memory += cells * 8.0 * std::max(1, max_threads());
      output += cells * 40.0;
    }
  }
  const std::string sizes = "(" + num(records) + " records x " + num(samples) + " samples";
  return {{Resource::Steps, records * (samples - 1.0 + burn) * o.substeps,
           "integration steps (" + num(records) + " records x " +
               (burn > 0 ? "(" + num(samples) + " samples + " + num(burn) + " of burn_in)" : num(samples) + " samples") +
               " x " + std::to_string(o.substeps) + " substeps)",
           "use fewer trajectories, a shorter duration or burn_in, fewer substeps or a larger dt"},
          {Resource::Memory, memory, sizes + ")", "use fewer or shorter records, or ask only for statistics"},
          {Resource::Output, output, sizes + ")", "use fewer or shorter records, or write .npy instead of CSV"}};
}

}  // namespace

SimulateJob simulate_job_from_config(const Config& c, const std::vector<std::vector<double>>* drive) {
  SimulateJob job;
  job.config_file = c.file();
  ModelFile model_file = model_from_config_value(c.raw("model"), c.where("model"));
  job.model = std::move(model_file.model);
  job.model_sections = std::move(model_file.sections);
  SimulationOptions& o = job.options;
  o.records = static_cast<int>(c.integer_in("trajectories", 1, 1000000000, 100));
  o.dt = c.positive_or("dt", 0.001);
  const double duration = c.positive_or("duration", 100.0);
  const double ratio = duration / o.dt;
  const double samples = std::round(ratio);
  if (std::abs(ratio - samples) > 1e-6 * std::max(1.0, ratio))
    c.fail("duration", "must be a whole number of dt (duration / dt = " + num(ratio) + ")");
  if (samples < 2) c.fail("duration", "must be at least 2·dt (a record needs 2 samples)");
  if (samples > 1e12) c.fail("duration", "gives more than 1e12 samples per record");
  o.samples = static_cast<std::size_t>(samples);
  const long long substeps = c.integer_at_least("substeps", 1, 1);
  if (substeps > 1000000) c.fail("substeps", "must be <= 1e6");
  o.substeps = static_cast<int>(substeps);
  o.scheme = enum_from_string(kSchemeNames, c.string_or("scheme", "taylor15"), c.where("scheme"));
  const long long seed = c.integer_or("seed", 1);
  if (seed < 0) c.fail("seed", "must be >= 0");
  o.seed = static_cast<std::uint64_t>(seed);
  const long long first = c.integer_or("first_record", 0);
  if (first < 0) c.fail("first_record", "must be >= 0");
  o.first_record = static_cast<std::uint64_t>(first);

  // initial conditions
  if (c.has("x0")) {
    double lo = 0, hi = 0;
    const auto& v = c.raw("x0");
    if (parse_uniform(c, "x0", lo, hi)) {
      o.x0.uniform = true;
      o.x0.lo = lo;
      o.x0.hi = hi;
    } else if (v.is_array()) {
      o.x0.uniform = false;
      o.x0.values = number_list(c, "x0", static_cast<std::size_t>(o.records));
    } else if (v.is_number()) {
      o.x0.uniform = false;
      o.x0.values.assign(static_cast<std::size_t>(o.records), c.number("x0"));
    } else {
      c.fail("x0", "must be {\"uniform\": [a, b]}, a number or a list of numbers");
    }
  }
  if (c.has("y0")) {
    double lo = 0, hi = 0;
    const auto& v = c.raw("y0");
    if (parse_uniform(c, "y0", lo, hi)) {
      o.x0.y_uniform = true;
      o.x0.y_lo = lo;
      o.x0.y_hi = hi;
    } else if (v.is_array()) {
      o.x0.y_values = number_list(c, "y0", static_cast<std::size_t>(o.records));
    } else if (v.is_number()) {
      o.x0.y0 = c.number("y0");
    } else {
      c.fail("y0", "must be a number, {\"uniform\": [a, b]} or a list of numbers");
    }
  }
  o.burn_in = c.non_negative_or("burn_in", 0.0);
  o.sensor_noise = c.non_negative_or("sensor_noise", 0.0);
  job.record_velocity = c.boolean_or("record_velocity", true);
  o.record_y = job.record_velocity;
  o.divergence_bound = c.positive_or("divergence_bound", 1e8);
  o.allow_unconfined = c.boolean_or("allow_unconfined", false);

  // drive
  if (drive) {
    if (c.has("drive")) c.fail("drive", "is given both as a file and in memory");
    assign_drive(c, "the drive", *drive, o);
  } else if (c.has("drive")) {
    const Config d = c.object("drive", {"path", "column", "t_column"});
    ReadOptions ro;
    ro.x_column = d.string_or("column", "u");
    ro.t_column = d.string_or("t_column", "t");
    ro.dt = o.dt;
    ro.read_u = false;
    const std::string path = d.path("path");
    const Dataset file = read_measurements(path, ro);
    std::vector<std::vector<double>> series;
    for (const auto& r : file.records) {
      if (std::abs(r.dt - o.dt) > 1e-6 * o.dt)
        c.fail("drive", path + " record " + std::to_string(r.id) + " is sampled at " + num(r.dt) +
                            " but dt = " + num(o.dt) + " (resample the drive first)");
      series.emplace_back(file.x_of(r), file.x_of(r) + r.size);
    }
    assign_drive(c, path, std::move(series), o);
  }

  if (c.has("output")) {
    job.output = c.path("output");
    if (job.output.empty()) c.fail("output", "must be a file path");
    for (const char* binary : {".mat", ".npz", ".h5", ".hdf5", ".xlsx", ".xls", ".parquet"})  // CSV text under a binary name
      if (std::filesystem::path(job.output).extension() == binary)
        c.fail("output", "'" + job.output + "' names a " + binary + " file, which simulate-vehs does not write (.npy: NumPy binary; any other name: CSV)");
  }
  if (c.has("statistics")) {
    const Config s = c.object("statistics", {"output", "discard", "grid", "px", "py", "pxy", "batches", "parameters"});
    job.with_statistics = true;
    job.power_parameters = s.boolean_or("parameters", false);
    if (job.power_parameters) (void)uncertain_parameters(job.model, s.where("parameters"));
    job.statistics_json = s.path("output");
    job.statistics.discard = s.non_negative_or("discard", 0.0);
    job.statistics.batches = static_cast<std::size_t>(s.integer_at_least("batches", 2, 32));
    if (s.has("grid")) {
      const Config g = s.object("grid", {"x", "y"});
      job.statistics.histograms = true;
      read_grid_axis(g, "x", job.statistics.x_min, job.statistics.x_max, job.statistics.nx);
      read_grid_axis(g, "y", job.statistics.y_min, job.statistics.y_max, job.statistics.ny);
      job.px_csv = s.path_or("px", beside(job.statistics_json, "_px.csv"));
      job.py_csv = s.path_or("py", beside(job.statistics_json, "_py.csv"));
      job.pxy_csv = s.path_or("pxy", beside(job.statistics_json, "_pxy.csv"));
    } else if (s.has("px") || s.has("py") || s.has("pxy")) {
      s.fail("grid", "is needed for histograms (px, py, pxy)");
    }
    if (auto why = job.statistics.invalid_reason(); !why.empty()) c.fail("statistics", why);
    const double discarded = static_cast<double>(std::llround(job.statistics.discard / o.dt));
    if (discarded >= static_cast<double>(o.samples))
      s.fail("discard", "leaves no samples (records last " + num(duration) + ")");
    if (s.has("batches")) {  // batch means are used only with fewer than 16 records; a batch needs >= 100 samples
      if (o.records >= job.statistics.min_records_for_spread)
        s.fail("batches", "is not used: with " + std::to_string(o.records) + " >= " +
                              std::to_string(job.statistics.min_records_for_spread) +
                              " records the standard errors come from the spread of the records");
      const double kept = static_cast<double>(o.samples) - discarded;
      if (static_cast<double>(job.statistics.batches) * 100.0 > kept)
        s.fail("batches", "= " + std::to_string(job.statistics.batches) + " leaves fewer than 100 samples per batch (" +
                              num(kept) + " samples per record after 'discard')");
    }
  }
  job.harvester = harvester_block(c);
  if (job.harvester.empty() && job.model_sections.contains("harvester")) job.harvester = job.model_sections["harvester"];
  if (job.output.empty() && !job.with_statistics)
    throw Error(c.file() + ": give 'output' (records) and/or 'statistics' — nothing would be written");
  if (c.has("summary")) job.summary = c.path("summary");
  if (c.has("record_phases"))
    job.record_phases = number_list(c, "record_phases", static_cast<std::size_t>(o.records));
  else if (job.model.fit && job.model.fit->likelihood &&
           job.model.fit->likelihood->record_phases.size() == static_cast<std::size_t>(o.records))
    job.record_phases = job.model.fit->likelihood->record_phases;
  if (!job.record_phases.empty()) {
    if (!job.model.find_effect(EffectId::HarmonicForcing))
      c.fail("record_phases", "needs a model with a harmonic_forcing effect");
    if (job.with_statistics) c.fail("record_phases", "cannot be combined with 'statistics'");
  }

  if (auto why = o.invalid_reason(); !why.empty()) throw Error(c.file() + ": " + why);
  check_budget(c, simulate_estimates(job));
  if (forced(c)) o.memory_limit = std::numeric_limits<double>::infinity();
  // model errors name the model file (or the config key of an inline model)
  check_simulation(job.model, o, c.raw("model").is_string() ? c.raw("model").get<std::string>() : c.where("model"));
  return job;
}

namespace {

/// Every `factor`-th sample of every record, recorded at `dt`.
void decimate(Dataset& d, std::size_t factor, double dt) {
  Dataset out;
  for (const auto& r : d.records) {
    Record rec = r;
    rec.offset = out.x.size();
    rec.dt = dt;
    rec.size = (r.size - 1) / factor + 1;
    for (std::size_t i = 0; i < rec.size; ++i) {
      out.x.push_back(d.x[r.offset + i * factor]);
      if (!d.y.empty()) out.y.push_back(d.y[r.offset + i * factor]);
      if (!d.u.empty()) out.u.push_back(d.u[r.offset + i * factor]);
    }
    out.records.push_back(rec);
  }
  d = std::move(out);
}

}  // namespace

SimulateRun simulate_job(const SimulateJob& job, const ProgressCallback& progress) {
  SimulationOptions o = job.options;
  o.progress = progress;
  SimulateRun run;
  SimulationSummary& summary = run.summary;
  Dataset& data = run.data;
  // A model fitted with an interpolated input (estimator.input) is driven the same way: the
  // simulator holds its drive per step, so it steps at dt/substeps with the interpolated input
  // at each step's midpoint and every substeps-th sample is kept.
  const InputInterpolation how = job.model.fit ? job.model.fit->input : InputInterpolation::ZeroOrderHold;
  const bool interpolated = how != InputInterpolation::ZeroOrderHold && (!o.drive.empty() || !o.drive_per_record.empty());
  const auto factor = static_cast<std::size_t>(o.substeps);
  if (interpolated) {
    const std::size_t series = o.drive.empty() ? o.drive_per_record.size() : 1;
    o.dt /= static_cast<double>(factor);
    o.samples = (o.samples - 1) * factor + 1;
    o.substeps = 1;
    // the refined drives (samples × substeps each) only once the simulator's limit allows them
    check_memory(o, true, static_cast<double>(series) * static_cast<double>(o.samples));
    if (!o.drive.empty()) o.drive = likelihood::refine_input(o.drive, static_cast<int>(factor), how);
    for (auto& u : o.drive_per_record) u = likelihood::refine_input(u, static_cast<int>(factor), how);
  }
  if (job.with_statistics) {
    run.statistics = simulate_statistics(job.model, o, job.statistics, &summary, job.output.empty() ? nullptr : &data);
    const RunEyy again = [&](const Model& m) { return simulate_statistics(m, o, job.statistics).moment("E[Y^2]"); };
    const nlohmann::json units = job.model_sections.contains("units") ? nlohmann::json(job.model_sections["units"])
                                                                       : nlohmann::json::object();
    run.power = power_section(job.model, run.statistics.moment("E[Y^2]"), units, job.harvester, job.power_parameters,
                              again, run.statistics.error_method);
  } else if (!job.record_phases.empty()) {
    // one run per record with its phase; first_record keeps each record's random stream
    SimulationOptions one = o;
    one.records = 1;
    one.drive_per_record.clear();
    for (std::size_t r = 0; r < job.record_phases.size(); ++r) {
      Model m = job.model;
      for (auto& e : m.effects)
        if (e.id == EffectId::HarmonicForcing) e.params["phase"] = job.record_phases[r];
      one.first_record = o.first_record + r;
      if (!o.drive_per_record.empty()) one.drive_per_record = {o.drive_per_record[r]};
      SimulationSummary part;
      Dataset d = simulate(m, one, &part);
      summary.steps += part.steps;
      summary.seconds += part.seconds;
      summary.records += part.records;
      summary.samples += part.samples;
      summary.threads = part.threads;
      summary.h = part.h;
      summary.scheme = part.scheme;
      data.append(std::move(d));
    }
    summary.steps_per_second = summary.seconds > 0 ? static_cast<double>(summary.steps) / summary.seconds : 0.0;
  } else {
    simulate(job.model, o, data, &summary);
  }
  if (interpolated) decimate(data, factor, job.options.dt);
  return run;
}

int run_simulate_job(const SimulateJob& job, const AppOptions& app) {
  const SimulationOptions& o = job.options;
  SimulateRun run = simulate_job(job, app.progress);
  const Dataset& data = run.data;
  const MonteCarloStatistics& stats = run.statistics;
  const SimulationSummary& summary = run.summary;

  if (!job.output.empty()) {
    WriteColumns cols;
    cols.with_y = job.record_velocity;
    cols.with_u = data.has_u();
    write_measurements(job.output, data, cols);
  }
  if (job.with_statistics) {
    nlohmann::ordered_json sim;
    sim["scheme"] = summary.scheme;
    sim["dt"] = o.dt;
    sim["substeps"] = o.substeps;
    sim["trajectories"] = o.records;
    sim["samples_per_record"] = o.samples;
    sim["burn_in"] = o.burn_in;
    sim["seed"] = o.seed;
    sim["first_record"] = o.first_record;
    nlohmann::ordered_json extra;
    extra["simulation"] = sim;
    extra["mean_power"] = run.power;
    extra["model"] = model_to_json(job.model, job.model_sections);  // lets vehs-compare check what it labels
    write_statistics(stats, job.statistics_json, job.px_csv, job.py_csv, job.pxy_csv, extra);
  }
  if (!job.summary.empty()) {
    nlohmann::ordered_json s;
    s["config"] = job.config_file;
    s["scheme"] = summary.scheme;
    s["dt"] = o.dt;
    s["substeps"] = o.substeps;
    s["h"] = summary.h;
    s["trajectories"] = summary.records;
    s["samples_per_record"] = o.samples;
    s["steps"] = summary.steps;
    s["seconds"] = summary.seconds;
    s["steps_per_second"] = summary.steps_per_second;
    s["threads"] = summary.threads;
    s["seed"] = o.seed;
    s["model"] = model_to_json(job.model, job.model_sections);
    write_json_atomically(job.summary, s);
  }
  if (!app.quiet) {
    std::fprintf(stderr,
                 "simulate-vehs: %zu records x %zu samples, %s, h = %g: %.3g steps in %.2f s "
                 "(%.1f M steps/s, %d threads)\n",
                 summary.records, o.samples, summary.scheme.c_str(), summary.h,
                 static_cast<double>(summary.steps), summary.seconds, summary.steps_per_second / 1e6,
                 summary.threads);
    if (!job.output.empty()) std::fprintf(stderr, "  records    -> %s\n", job.output.c_str());
    if (job.with_statistics) {
      const auto& ey2 = stats.moment("E[Y^2]");
      const auto& ex2 = stats.moment("E[X^2]");
      std::fprintf(stderr, "  statistics -> %s  (E[X^2] = %.5g ± %.2g, E[Y^2] = %.5g ± %.2g)\n",
                   job.statistics_json.c_str(), ex2.value, ex2.stderr_, ey2.value, ey2.stderr_);
      if (!run.power["watts"].is_null())
        std::fprintf(stderr, "  mean power %.5g W ± %.2g (%s)\n", run.power["watts"].get<double>(),
                     run.power["stderr"].get<double>(), run.power["error_method"].get<std::string>().c_str());
    }
  }
  return 0;
}

int run_simulate(Config& config, const AppOptions& app) {
  if (config.has("validate")) {
    const ModelFile mf = model_from_config_value(config.raw("model"), config.where("model"));
    validate_model(mf.model, config.where("model"));
    return run_validation(mf.model, config, app);
  }
  return run_simulate_job(simulate_job_from_config(config), app);
}

}  // namespace vehs::tools
