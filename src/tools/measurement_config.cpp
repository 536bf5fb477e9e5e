#include "tools/measurement_config.hpp"

#include "tools/data_checks.hpp"

#include <iostream>
#include <map>
#include <utility>

#include "vehs/core/detail/format.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/parameter_units.hpp"

namespace vehs::tools {

std::vector<KeySpec> measurement_keys() {
  return {
      {"measurement", "path",
       "A measurement file: a JSON object with any of the keys data, columns, mat_variable, dt, "
       "sampling, detrend, units, glitches and flat_stretches, describing a rig's recordings once "
       "for every config (identify, diagnose, vehs.read). The config's own keys win over the file's.",
       "", true},
      {"columns", "object | [names]",
       "Column names in the files: {\"x\": ..., \"t\": ..., \"u\": ..., \"traj\": ...} (traj: the record "
       "id; rows of one record are contiguous), e.g. {\"x\": \"V2\", \"u\": \"V1\"} for the Silverbox "
       "data. For a 2-D .npy array or a .mat matrix: the list of its columns' names in order, e.g. "
       "[\"t\", \"x\", \"u\"] (\"\" skips a column).",
       "{\"x\": \"x\", \"t\": \"t\", \"u\": \"u\", \"traj\": \"traj\"}"},
      {"mat_variable", "string",
       "A .mat file's matrix variable, read with the list of `columns`; without it every column is "
       "a vector variable named like the columns (t, x, u, traj).",
       "", true},
      {"dt", "number",
       "Sampling interval: used for files without a time column; with a time column the column is "
       "only checked against it (each step within sampling.jitter_tolerance, the mean of a record's steps within "
       "that tolerance divided by its steps).",
       "", true},
      {"sampling", "object",
       "Time-column tolerances: {\"jitter_tolerance\": 0.15 (largest relative deviation of a time "
       "step from the record's interval: rounded, float32 or jittered logger stamps), "
       "\"jitter_warning\": 1e-4 (a warning above), \"on_gap\": \"split\" | \"fail\" (a step longer "
       "than 1.5 intervals, or a row with an empty, NaN or infinite x, t or u: split the record there, "
       "dropping pieces shorter than 16 samples, or stop with an error naming the line)}. The counts "
       "are reported on stderr and in the output's data section.",
       "{\"jitter_tolerance\": 0.15, \"jitter_warning\": 1e-4, \"on_gap\": \"split\"}"},
      {"detrend", "string",
       "\"mean\": subtract each record's mean from x and u (DC offsets of real sensors); \"none\": use "
       "the data as they are.",
       "\"none\""},
      {"units", "object",
       "Units of the data, carried into the model file, the reports and figure axes: {\"length\": "
       "\"mm\", \"time\": \"s\", \"input\": \"V\"} (any text; m, mm, um, cm and s, ms, us are also "
       "understood as SI factors, which mean power in W needs). Coefficients are in these units "
       "(b2 in length/time^2, a22 in length^2/time^3).",
       "{} (non-dimensional)"},
      glitches_key_spec(),
      flat_stretches_key_spec(),
  };
}

namespace {

/// Two roles read from one column (t and x both "x": the time stamps would be the signal) are
/// an error naming both keys; a default counts when that role is read (u only with a drive).
void require_distinct_columns(const Config& col, const ReadOptions& r, bool need_u) {
  const std::pair<const char*, const std::string*> roles[] = {
      {"t", &r.t_column}, {"x", &r.x_column}, {"traj", &r.traj_column}, {"u", &r.u_column}};
  const std::size_t n = need_u ? 4 : 3;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const auto& [a, name_a] = roles[i];
      const auto& [b, name_b] = roles[j];
      if (*name_a != *name_b || !(col.has(a) || col.has(b))) continue;
      const std::string key_a = std::string("'columns.") + a + "'", key_b = std::string("'columns.") + b + "'";
      if (col.has(a) && col.has(b))
        throw Error(col.file() + ": " + key_a + " and " + key_b + " name the same column '" + *name_a + "'");
      const auto& [given, other] = col.has(a) ? std::pair(key_a, b) : std::pair(key_b, a);
      throw Error(col.file() + ": " + given + " names the column '" + *name_a + "', which is " + other +
                  "'s by default (give " + other + "'s column as 'columns." + other + "')");
    }
}

}  // namespace

ReadOptions read_options(const Config& c, bool need_u, bool read_present_u) {
  ReadOptions r;
  if (c.has("columns")) {
    if (c.raw("columns").is_array()) {
      r.columns = c.string_list("columns");
    } else {
      const Config col = c.object("columns", {"x", "t", "u", "traj"});
      r.x_column = col.string_or("x", r.x_column);
      r.t_column = col.string_or("t", r.t_column);
      r.u_column = col.string_or("u", r.u_column);
      r.traj_column = col.string_or("traj", r.traj_column);
      require_distinct_columns(col, r, need_u);
    }
  }
  r.mat_variable = c.string_or("mat_variable", "");
  if (c.has("dt")) r.dt = c.positive("dt");
  if (c.has("sampling")) {
    const Config s = c.object("sampling", {"jitter_tolerance", "jitter_warning", "on_gap"});
    r.jitter_tolerance = s.positive_or("jitter_tolerance", r.jitter_tolerance);
    if (!(r.jitter_tolerance < 0.5)) s.fail("jitter_tolerance", "must be < 0.5");
    r.jitter_warning = s.non_negative_or("jitter_warning", r.jitter_warning);
    const std::string on_gap = s.string_or("on_gap", "split");
    if (on_gap == "fail")
      r.on_gap = GapPolicy::Fail;
    else if (on_gap != "split")
      s.fail("on_gap", "must be \"split\" or \"fail\" (got \"" + on_gap + "\")");
  }
  r.require_u = need_u;
  // an input column present in the files is read when asked for, unless it is another role's column
  const bool u_distinct = r.u_column != r.x_column && r.u_column != r.t_column && r.u_column != r.traj_column;
  r.read_u = need_u || (read_present_u && u_distinct);
  r.read_y = false;
  r.min_samples = 16;
  return r;
}

LoadedData load_measurements(const Config& c, bool need_u, const AppOptions& app, bool read_present_u) {
  return load_measurements(c, read_options(c, need_u, read_present_u), app.quiet);
}

LoadedData load_measurements(const Config& c, const ReadOptions& options, bool quiet) {
  const auto files = c.path_list("data");
  if (files.empty()) c.fail("data", "lists no file");
  LoadedData l;
  l.data = checked_measurements(c, read_measurements(files, options, &l.summary));
  if (!quiet || l.summary.dropped_samples > 0)  // samples left out: said even with --quiet
    for (const auto& w : l.summary.warnings) std::cerr << "warning: " << w << "\n";
  l.detrend = c.string_or("detrend", "none");
  if (l.detrend == "mean")
    subtract_record_means(l.data);
  else if (l.detrend != "none")
    c.fail("detrend", "must be \"none\" or \"mean\" (got \"" + l.detrend + "\")");
  return l;
}

nlohmann::ordered_json read_summary_json(const ReadSummary& s) {
  return {{"gaps_split", s.gaps},
          {"missing_runs_split", s.missing_runs},
          {"missing_rows", s.missing_rows},
          {"dropped_pieces", s.dropped_pieces},
          {"dropped_samples", s.dropped_samples},
          {"max_time_jitter", s.max_jitter}};
}

nlohmann::ordered_json units_block(const Config& c) {
  nlohmann::ordered_json u = nlohmann::ordered_json::object();
  if (!c.has("units")) return u;
  const Config k = c.object("units", {"length", "time", "input"});
  for (const char* key : {"length", "time", "input"})
    if (k.has(key)) {
      const std::string v = k.string(key);
      if (v.empty() || v.find_first_of("\n\r") != std::string::npos) k.fail(key, "must be a non-empty one-line unit name");
      u[key] = v;
    }
  return u;
}

std::string with_unit(const std::string& label, const std::string& what, const nlohmann::json& units) {
  auto has = [&](const char* k) { return units.is_object() && units.contains(k) && units[k].is_string(); };
  static const std::map<std::string, Dimension> dimensions = {
      {"x", {1, 0, 0}},    {"t", {0, 1, 0}},   {"v", {1, -1, 0}},  {"u", {0, 0, 1}},   {"f", {0, -1, 0}},
      {"b2", {1, -2, 0}},  {"a22", {2, -3, 0}}, {"v2", {2, -2, 0}}, {"1/x", {-1, 0, 0}}, {"psd_x", {2, 1, 0}}};
  const auto it = dimensions.find(what);
  if (it == dimensions.end()) return label;
  if (what == "u" && !has("input")) return label;  // the drive has no unit of its own to name
  if (what == "x" && !has("length")) return label;  // x and v stay plain labels without units
  if (what == "v" && !has("length") && !has("time")) return label;
  return label + " [" + unit_text(it->second, units) + "]";  // the tables' rule (vehs/io/parameter_units.hpp)
}

std::string input_column_name(const Config& c) {
  if (!c.has("columns") || !c.raw("columns").is_object()) return "u";
  const auto& col = c.raw("columns");
  return col.contains("u") && col["u"].is_string() ? col["u"].get<std::string>() : "u";
}

}  // namespace vehs::tools
