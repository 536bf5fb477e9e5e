#include "tools/fpk_tool.hpp"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>

#include "tools/budget.hpp"
#include "tools/fpk_output.hpp"
#include "tools/power.hpp"
#include "vehs/conventions.hpp"
#include "vehs/core/detail/format.hpp"
#include "vehs/core/detail/memory.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/parameters.hpp"
#include "vehs/fpk/stationary.hpp"
#include "vehs/io/atomic_file.hpp"
#include "vehs/io/json_file.hpp"
#include "vehs/io/model_file.hpp"

namespace vehs::tools {

using namespace vehs::fpk;

namespace {

ConfigSchema make_schema() {
  ConfigSchema s;
  s.tool = "fpk-stationary";
  s.summary =
      "Solves the stationary Fokker-Planck equation 0 = -d/dx(y p) - d/dy(b2 p) + 1/2 d2/dy2(a22 p) "
      "of the model dX = Y dt, dY = b2 dt + sqrt(a22) dB on a cell-centred grid and writes the "
      "density, its marginals, E[X^2], E[Y^2], E[XY], the mass per potential well and exact-identity "
      "checks; optionally sweeps one or two model parameters.";
  s.keys = {
      {"model", "object|path", "The model (docs/model-file.md): an inline object or the path of a "
                               "model file written by identify-vehs. Supports every drift term except "
                               "'u', diffusion monomials, and the impact_stop effect.", ""},
      {"output", "path", "Statistics JSON: E[X^2], E[Y^2], E[XY], boundary_mass, grid, wells, "
                         "identities, solver summary, file names.", ""},
      {"grid", "object", "{\"x\": [min, max, n] or n, \"y\": [min, max, n] or n}. An axis given as a "
                         "number n (or omitted) gets an automatic range from the potential and the "
                         "noise, widened until at most boundary_mass_tolerance of the mass is in its "
                         "edge cells; a given range that holds more is an error. Cells that do not "
                         "resolve the model (an undershooting density, or boundary mass that does not "
                         "fall as the domain widens) are doubled on automatic axes up to 800 per "
                         "axis (grid.refinements in the output), else the error names the cells needed.",
       "{\"x\": 400, \"y\": 400}"},
      {"scheme", "string", "flux: conservative finite volumes, 4th-order x-flux, 2nd-order y "
                           "(default; mass conserved exactly, L1 error 1.3e-4 at 400x400 on the exact "
                           "Q=0 test); flux2: conservative, 2nd order in both (compact, faster, 4x "
                           "larger error); central: the paper's Eq. 35 with correct central "
                           "differences (not conservative); paper_literal: Eq. 35 as printed "
                           "(dp/dx ~ (p[i+1]-p[i-1])/dx), inconsistent, for comparison only.",
       "\"flux\""},
      {"solver", "string", "direct: UMFPACK sparse LU with a normalisation row; sor: the paper's "
                           "relaxed Gauss-Seidel (settings in 'sor'); bicgstab: ILUT-preconditioned "
                           "BiCGSTAB (settings in 'iterative').", "\"direct\""},
      {"ordering", "string", "Fill-reducing ordering of the direct solver: auto (AMD for one solve, "
                             "METIS for sweeps, where its costlier analysis is shared), metis or amd.",
       "\"auto\""},
      {"correction_steps", "integer", "Direct solver with scheme flux: factorise the compact flux2 "
                                      "operator and take this many defect-correction steps towards "
                                      "the fourth-order one (0: factorise the 7-point operator "
                                      "itself, ~2x slower, same result on resolved grids).", "2"},
      {"sor", "object", "{\"alpha\": relaxation factor (paper 0.01), \"tolerance\": stop when "
                        "max|dp|/max p < tolerance (paper 1e-5), \"max_iterations\", "
                        "\"normalize_every\": sweeps between normalisations (paper 10)}.",
       "{\"alpha\": 0.01, \"tolerance\": 1e-5, \"max_iterations\": 1000000, \"normalize_every\": 10}"},
      {"iterative", "object", "{\"tolerance\": relative residual, \"max_iterations\", "
                              "\"drop_tolerance\", \"fill_factor\"} of the bicgstab solver.",
       "{\"tolerance\": 1e-10, \"max_iterations\": 20000, \"drop_tolerance\": 1e-4, \"fill_factor\": 20}"},
      {"boundary_mass_tolerance", "number", "Largest probability mass allowed in the outermost ring of "
                                            "cells (contract: 1e-6). Raise it only to reproduce a "
                                            "published grid that is too small.", "1e-6"},
      {"auto_domain_efolds", "number", "Automatic ranges end where the local-equilibrium density has "
                                       "dropped by exp(-K) from its peak.", "25"},
      {"density", "path", "Density file: .npy (float64, shape (nx, ny)) or CSV (x,y,p). Marginals "
                          "go beside it as <stem>.marginal_x.csv (x,p,U) and <stem>.marginal_y.csv.",
       "<output stem>.density.csv"},
      harvester_key(),
      {"figures", "path", "Folder for SVG figures (density heat map, marginals with the potential and "
                          "well boundaries, sweep curves or surfaces), each with its data and gnuplot "
                          "script.", "", true},
      {"sweep", "object", "One or two model parameters, each [min, max, n] (n evenly spaced values) or "
                          "{\"values\": [...]}: e.g. {\"2D\": [0.01, 0.03, 9], \"2Q\": [0.005, 0.02, "
                          "7]}. Names: beta, k<i>, 2D, 2Q, D, Q, drift[<term>], diffusion[<term>], "
                          "<effect>.<param> (coulomb_friction.mu = -drift[sign(y)], impact_stop.gap, ...) "
                          "or an effect's parameter alone (mu). All points share one grid (automatic axes: the "
                          "envelope of all points' ranges) and one symbolic factorisation; points run "
                          "in parallel (--threads).", "", true},
      {"sweep_table", "path", "CSV of the sweep, one row per point.", "<output stem>.sweep.csv"},
      force_key(),
  };
  s.epilog =
      "Example: {\"model\": \"learned.json\", \"output\": \"out/fpk.json\", \"figures\": \"out/fig\"}\n"
      "Outputs are written atomically. Exit status: 0 ok, 1 bad input or unsolvable model, 2 usage.";
  return s;
}

std::string stem_of(const std::string& path) {
  const std::filesystem::path p(path);
  return (p.parent_path() / p.stem()).string();
}

constexpr long long kMaxCellsPerAxis = 20000;  // Grid::invalid_reason's limit
constexpr double kMaxEfolds = 100.0;
// SOR: sweeps x cells, about a minute of work on one core (the paper's alpha = 0.01 needs ~1e5
// sweeps); more is an error before the solve, not a run without end
constexpr double kMaxSorCellUpdates = 2e10;

GridRequest parse_grid(const Config& cfg) {
  GridRequest req;
  req.grid.x.n = 400;
  req.grid.y.n = 400;
  if (!cfg.has("grid")) return req;
  const Config g = cfg.object("grid", {"x", "y"});
  for (const char* ax : {"x", "y"}) {
    if (!g.has(ax)) continue;
    const auto& v = g.raw(ax);
    Axis& a = std::string(ax) == "x" ? req.grid.x : req.grid.y;
    bool& automatic = std::string(ax) == "x" ? req.auto_x : req.auto_y;
    if (v.is_number_integer()) {
      const long long n = g.integer(ax);
      if (n < 3 || n > kMaxCellsPerAxis)
        g.fail(ax, "must have from 3 to " + std::to_string(kMaxCellsPerAxis) + " cells (got " + std::to_string(n) + ")");
      a.n = static_cast<int>(n);
      automatic = true;
    } else if (v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() &&
               v[2].is_number_integer()) {
      a.min = v[0].get<double>();
      a.max = v[1].get<double>();
      const long long n = json_integer(v[2]).value_or(-1);
      if (!(std::isfinite(a.min) && std::isfinite(a.max) && a.min < a.max))
        g.fail(ax, "needs min < max (got [" + json_excerpt(v[0]) + ", " + json_excerpt(v[1]) + "])");
      if (n < 3 || n > kMaxCellsPerAxis)
        g.fail(ax, "must have from 3 to " + std::to_string(kMaxCellsPerAxis) + " cells (got " + json_excerpt(v[2]) + ")");
      a.n = static_cast<int>(n);
      automatic = false;
    } else {
      g.fail(ax, "must be [min, max, n] with integer n, or a cell count n (got " + json_excerpt(v) + ")");
    }
  }
  return req;
}

std::vector<SweepAxis> parse_sweep(const Config& cfg) {
  std::vector<SweepAxis> axes;
  const Config s = cfg.object("sweep");
  for (auto it = s.json().begin(); it != s.json().end(); ++it) {
    SweepAxis a;
    a.name = it.key();
    const auto& v = it.value();
    if (v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() && v[2].is_number_integer()) {
      const double lo = v[0].get<double>(), hi = v[1].get<double>();
      const long long n = json_integer(v[2]).value_or(-1);
      if (n < 1 || n > 100000) s.fail(a.name, "needs 1 <= n <= 100000 (got " + json_excerpt(v[2]) + ")");
      for (long long k = 0; k < n; ++k)
        a.values.push_back(n == 1 ? lo : lo + (hi - lo) * static_cast<double>(k) / static_cast<double>(n - 1));
    } else if (v.is_object() && v.size() == 1 && v.contains("values") && v["values"].is_array() &&
               !v["values"].empty()) {
      for (const auto& x : v["values"]) {
        if (!x.is_number()) s.fail(a.name, "values must be numbers");
        a.values.push_back(x.get<double>());
      }
    } else {
      s.fail(a.name, "must be [min, max, n] or {\"values\": [...]} (got " + json_excerpt(v) + ")");
    }
    axes.push_back(a);
  }
  if (axes.empty() || axes.size() > 2) cfg.fail("sweep", "needs one or two parameters");
  return axes;
}

/// Work, memory and output of the solves (docs/config.md, Budgets).
std::vector<Estimate> fpk_estimates(const Config& cfg, const FpkSettings& st) {
  const double cells = static_cast<double>(st.grid.grid.x.n) * static_cast<double>(st.grid.grid.y.n);
  double solves = 1.0;  // the model itself, then every sweep point
  if (!st.axes.empty()) {
    double points = 1.0;
    for (const auto& a : st.axes) points *= static_cast<double>(a.values.size());
    solves += points;
  }
  const std::string sizes = "(" + vehs::detail::format_number(cells, 6) + " cells x " +
                            vehs::detail::format_number(solves, 6) + " solves)";
  std::vector<Estimate> out;
  if (st.solve.solver == Solver::Direct)
    out.push_back({Resource::CellSolves, cells * solves, "cell solves " + sizes, "use fewer grid cells or sweep points"});
  if (st.solve.solver == Solver::Bicgstab)
    out.push_back({Resource::Steps, cells * solves * st.solve.iterative.max_iterations,
                   "cell updates (iterative.max_iterations " + std::to_string(st.solve.iterative.max_iterations) + " x " +
                       sizes.substr(1),
                   "use fewer grid cells, sweep points or iterative.max_iterations, or the direct solver"});
  out.push_back({Resource::Memory, estimated_solve_bytes(static_cast<std::size_t>(cells), st.solve),
                 "per solve (" + vehs::detail::format_number(cells, 6) + " cells)", "use fewer grid cells"});
  const bool npy = std::filesystem::path(cfg.string_or("density", "")).extension() == ".npy";
  out.push_back({Resource::Output, cells * (npy ? 8.0 : 40.0), "of density (" + vehs::detail::format_number(cells, 6) + " cells)",
                 "use fewer grid cells or a .npy density"});
  return out;
}

}  // namespace

const ConfigSchema& fpk_schema() {
  static const ConfigSchema schema = make_schema();
  return schema;
}

FpkSettings fpk_settings(const Config& cfg) {
  FpkSettings st;
  SolveOptions& opt = st.solve;
  opt.scheme = enum_from_string(kSchemeNames, cfg.string_or("scheme", "flux"), cfg.where("scheme"));
  opt.solver = enum_from_string(kSolverNames, cfg.string_or("solver", "direct"), cfg.where("solver"));
  opt.ordering = enum_from_string(kOrderingNames, cfg.string_or("ordering", "auto"), cfg.where("ordering"));
  opt.correction_steps = cfg.int_at_least("correction_steps", 0, opt.correction_steps);
  // settings of a solver that is not used would be ignored silently
  if (cfg.has("sor") && opt.solver != Solver::Sor) cfg.fail("sor", "is given but 'solver' is not \"sor\"");
  if (cfg.has("iterative") && opt.solver != Solver::Bicgstab)
    cfg.fail("iterative", "is given but 'solver' is not \"bicgstab\"");
  if (cfg.has("sor")) {
    const Config s = cfg.object("sor", {"alpha", "tolerance", "max_iterations", "normalize_every"});
    opt.sor.alpha = s.positive_or("alpha", opt.sor.alpha);
    opt.sor.tolerance = s.positive_or("tolerance", opt.sor.tolerance);
    opt.sor.max_iterations = s.integer_at_least("max_iterations", 1, opt.sor.max_iterations);
    opt.sor.normalize_every = s.int_at_least("normalize_every", 1, opt.sor.normalize_every);
  }
  if (cfg.has("iterative")) {
    const Config s = cfg.object("iterative", {"tolerance", "max_iterations", "drop_tolerance", "fill_factor"});
    opt.iterative.tolerance = s.positive_or("tolerance", opt.iterative.tolerance);
    opt.iterative.max_iterations = s.int_at_least("max_iterations", 1, opt.iterative.max_iterations);
    opt.iterative.drop_tolerance = s.non_negative_or("drop_tolerance", opt.iterative.drop_tolerance);
    opt.iterative.fill_factor = s.int_at_least("fill_factor", 1, opt.iterative.fill_factor);
  }
  if (auto why = opt.invalid_reason(); !why.empty()) throw Error(cfg.file() + ": " + why);
  DomainOptions& dom = st.domain;
  dom.boundary_mass_tolerance = cfg.positive_or("boundary_mass_tolerance", dom.boundary_mass_tolerance);
  dom.log_density_drop = cfg.positive_or("auto_domain_efolds", dom.log_density_drop);
  if (dom.log_density_drop > kMaxEfolds)
    cfg.fail("auto_domain_efolds", "must be at most " + std::to_string(static_cast<int>(kMaxEfolds)) +
                                       " (the domain edge has density e^-K of the peak; 25 is plenty)");
  st.grid = parse_grid(cfg);
  const GridRequest& req = st.grid;
  if (opt.solver == Solver::Sor) {
    const double updates = static_cast<double>(opt.sor.max_iterations) * req.grid.x.n * req.grid.y.n;
    if (updates > kMaxSorCellUpdates)
      cfg.fail(cfg.has("sor") ? "sor" : "solver",
               "sor: max_iterations " + std::to_string(opt.sor.max_iterations) + " x " +
                   std::to_string(req.grid.x.n * req.grid.y.n) + " cells is more than the 2e10 cell " +
                   "updates allowed: lower sor.max_iterations to " + std::to_string(static_cast<long long>(kMaxSorCellUpdates /
                   (req.grid.x.n * static_cast<double>(req.grid.y.n)))) + " or less, or use the direct solver");
  }
  if (cfg.has("sweep")) st.axes = parse_sweep(cfg);  // parse and check before the long solve
  check_budget(cfg, fpk_estimates(cfg, st));
  if (forced(cfg)) st.solve.memory_limit = std::numeric_limits<double>::infinity();
  return st;
}

int run_fpk(Config& cfg, const AppOptions& app) {
  const ModelFile model_file = model_from_config_value(cfg.raw("model"), cfg.where("model"));
  const Model& model = model_file.model;
  const std::string model_where =
      cfg.raw("model").is_string() ? cfg.raw("model").get<std::string>() : cfg.where("model");
  const FpkModel fm(model, model_where);
  const std::string output = cfg.path("output");
  FpkSettings st = fpk_settings(cfg);
  if (st.solve.solver == Solver::Sor) st.solve.sor.progress = app.progress;
  const SolveOptions& opt = st.solve;
  const DomainOptions& dom = st.domain;
  const GridRequest& req = st.grid;
  const std::vector<SweepAxis>& axes = st.axes;
  if (!app.quiet) {
    st.solve.log = [](const std::string& line) { std::cerr << "fpk-stationary: " << line << "\n"; };
    const std::size_t cells = static_cast<std::size_t>(req.grid.x.n) * req.grid.y.n;
    const double bytes = estimated_solve_bytes(cells, opt), seconds = estimated_solve_seconds(cells, opt);
    if (bytes > 1e9 || seconds > 5.0)
      std::cerr << "fpk-stationary: " << req.grid.x.n << "x" << req.grid.y.n << " cells: about "
                << vehs::detail::format_number(bytes / 1e9, 2) << " GB of memory per solve (limit "
                << vehs::detail::format_number(vehs::detail::default_memory_limit(opt.memory_limit) / 1e9, 2)
                << " GB: 3/4 of physical memory)"
                << (seconds > 0.0 ? " and about " + vehs::detail::format_number(seconds, 2) +
                                        " s on one idle core; the factorisation reports no progress from inside "
                                        "(Ctrl-C stops it, leaving no files)"
                                  : std::string())
                << "\n";
  }
  for (const auto& a : axes) {
    try {
      (void)get_parameter(model, a.name);
    } catch (const Error& e) {
      throw Error(cfg.where("sweep") + ": " + e.what());
    }
  }

  const StationaryResult res = solve_with_domain(fm, req, opt, dom);
  nlohmann::ordered_json out = result_to_json(res);
  const std::string density = cfg.path_or("density", stem_of(output) + ".density.csv");
  const std::string dstem = stem_of(density);
  write_density(density, res);
  write_marginals(dstem + ".marginal_x.csv", dstem + ".marginal_y.csv", fm, res);
  out["density_file"] = density;
  out["marginal_x_file"] = dstem + ".marginal_x.csv";
  out["marginal_y_file"] = dstem + ".marginal_y.csv";
  auto figures = nlohmann::ordered_json::array();
  if (cfg.has("figures"))
    for (const auto& f : density_figures(cfg.path("figures"), fm, res,
                                         model_file.sections.contains("units") ? nlohmann::json(model_file.sections["units"])
                                                                               : nlohmann::json::object()))
      figures.push_back(f);
  if (!axes.empty()) {
    SweepOptions so;
    so.solve = opt;
    so.domain = dom;
    so.progress = app.progress;
    const SweepResult sw = sweep(model, axes, req, so);
    std::size_t failed = 0;
    for (const auto& p : sw.points) {
      if (p.error.empty()) continue;
      ++failed;
      std::string at;
      for (std::size_t a = 0; a < axes.size(); ++a)
        at += (a ? ", " : "") + axes[a].name + " = " + vehs::detail::format_number(p.parameters[a], 6);
      std::cerr << "fpk-stationary: warning: sweep point " << at << " failed: " << p.error << "\n";
    }
    if (failed == sw.points.size())
      throw Error(cfg.where("sweep") + ": every point failed (first: " + sw.points.front().error + ")");
    const std::string table = cfg.path_or("sweep_table", stem_of(output) + ".sweep.csv");
    write_sweep_table(table, sw);
    out["sweep"] = sweep_to_json(sw);
    out["sweep"]["table"] = table;
    if (cfg.has("figures"))
      for (const auto& f : sweep_figures(cfg.path("figures"), sw)) figures.push_back(f);
  }
  if (cfg.has("figures")) out["figures"] = figures;
  const nlohmann::json units = model_file.sections.contains("units") ? nlohmann::json(model_file.sections["units"])
                                                                      : nlohmann::json::object();
  nlohmann::json harvester = harvester_block(cfg);
  if (harvester.empty() && model_file.sections.contains("harvester")) harvester = model_file.sections["harvester"];
  const MeanPower power = mean_power(res.moments.eyy, units, harvester);
  out["mean_power"] = {{"watts", power.available ? nlohmann::json(power.watts) : nlohmann::json(nullptr)},
                       {"how", power.formula}};
  if (!units.empty()) out["units"] = units;
  out["model"] = model_to_json(model, model_file.sections);
  write_json_atomically(output, out);
  if (!app.quiet)
    std::cerr << "fpk-stationary: E[X^2] = " << res.moments.exx << ", E[Y^2] = " << res.moments.eyy
              << ", boundary mass " << res.boundary_mass << " on " << res.grid.x.n << "x"
              << res.grid.y.n << " cells"
              << (res.refinements > 0 ? " (refined " + std::to_string(res.refinements) +
                                            " time(s): the requested grid did not resolve the model)"
                                      : std::string())
              << " (" << res.summary.solve_seconds << " s) -> " << output << "\n"
              << (power.available ? "fpk-stationary: mean power " + vehs::detail::format_number(power.watts, 4) + " W (" +
                                        power.formula + ")\n"
                                  : std::string());
  return 0;
}

}  // namespace vehs::tools
