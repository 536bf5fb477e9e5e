// vehs.stationary and the sweep: fpk-stationary's keys; the density handed to NumPy without a
// copy; sweeps solved whole or by blocks of points that merge exactly (SweepOptions::block_*).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>

#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "bindings.hpp"
#include "bridge.hpp"
#include "records.hpp"
#include "tools/fpk_output.hpp"
#include "tools/fpk_tool.hpp"
#include "tools/power.hpp"
#include "vehs/core/parameters.hpp"

namespace vehs::python {

namespace {

/// A solved density, kept for NumPy views.
struct Stationary {
  std::shared_ptr<fpk::StationaryResult> result = std::make_shared<fpk::StationaryResult>();
  nlohmann::ordered_json power;  ///< fpk-stationary's "mean_power"
};

Column view(nb::handle self, std::vector<double>& v) {
  const std::size_t shape[1] = {v.size()};
  return Column(v.data(), 1, shape, self);
}

tools::FpkSettings settings(const std::string& options_json, const char* where) {
  const tools::Config c = config_from_json(options_json, where, tools::fpk_schema(),
                                           {"model", "output", "density", "figures", "sweep_table"});
  return tools::fpk_settings(c);
}

Stationary stationary(const ModelFile& model, const std::string& options_json, nb::object progress) {
  const tools::FpkSettings st = settings(options_json, "vehs.stationary");
  require(st.axes.empty(), "vehs.stationary: 'sweep' belongs to vehs.sweep");
  const fpk::FpkModel fm(model.model, "vehs.stationary: model");
  Stationary out;
  *out.result = run_released(std::move(progress), false, [&](const ProgressCallback&) {
    return fpk::solve_with_domain(fm, st.grid, st.solve, st.domain);
  });
  const tools::Config c = config_from_json(options_json, "vehs.stationary", tools::fpk_schema(),
                                           {"model", "output", "density", "figures", "sweep_table"});
  nlohmann::json harvester = tools::harvester_block(c);
  if (harvester.empty() && model.sections.contains("harvester")) harvester = model.sections["harvester"];
  const nlohmann::json units = model.sections.contains("units") ? nlohmann::json(model.sections["units"]) : nlohmann::json::object();
  const tools::MeanPower p = tools::mean_power(out.result->moments.eyy, units, harvester);
  out.power = {{"watts", p.available ? nlohmann::json(p.watts) : nlohmann::json(nullptr)}, {"how", p.formula}};
  return out;
}

/// A sweep's settings from keyword options, with its parameters checked against the model.
tools::FpkSettings sweep_settings(const ModelFile& model, const std::string& options_json) {
  tools::FpkSettings st = settings(options_json, "vehs.sweep");
  require(!st.axes.empty(), "vehs.sweep: give 'sweep' (one or two parameters)");
  for (const auto& a : st.axes) (void)get_parameter(model.model, a.name);
  return st;
}

fpk::SweepOptions sweep_options(const tools::FpkSettings& st) {
  fpk::SweepOptions so;
  so.solve = st.solve;
  so.domain = st.domain;
  return so;
}

/// A sweep's plan (fpk::SweepPlan) for blocks of points solved apart: made once on a client
/// (sweep_plan: the grid and the point errors as JSON, exact doubles), analysed once per worker
/// process (SweepPlan(model, options, plan_json), kept there for every block of that sweep).
struct SweepPlan {
  std::shared_ptr<fpk::SweepPlan> plan = std::make_shared<fpk::SweepPlan>();
};

std::string sweep_plan_json(const ModelFile& model, const std::string& options_json) {
  const tools::FpkSettings st = sweep_settings(model, options_json);
  fpk::SweepPlan plan = run_released(nb::none(), false, [&](const ProgressCallback&) {
    return fpk::plan_sweep(model.model, st.axes, st.grid, sweep_options(st));
  });
  const auto axis = [](const fpk::Axis& a) { return nlohmann::ordered_json::array({a.min, a.max, a.n}); };
  nlohmann::ordered_json j;
  j["grid"] = {{"x", axis(plan.grid.x)}, {"y", axis(plan.grid.y)}};
  j["errors"] = plan.errors;
  return json_text(j);
}

SweepPlan analysed_plan(const ModelFile& model, const std::string& options_json, const std::string& plan_json) {
  const tools::FpkSettings st = sweep_settings(model, options_json);
  const nlohmann::json j = nlohmann::json::parse(plan_json);
  SweepPlan out;
  fpk::SweepPlan& p = *out.plan;
  for (auto [axis, key] : {std::pair{&p.grid.x, "x"}, std::pair{&p.grid.y, "y"}}) {
    axis->min = j.at("grid").at(key).at(0).get<double>();
    axis->max = j.at("grid").at(key).at(1).get<double>();
    axis->n = j.at("grid").at(key).at(2).get<int>();
  }
  p.errors = j.at("errors").get<std::vector<std::string>>();
  run_released(nb::none(), false, [&](const ProgressCallback&) {
    fpk::analyse_sweep(p, model.model, st.axes, sweep_options(st));
  });
  return out;
}

/// The sweep's JSON (fpk-stationary's "sweep" section); with last > 0 only the points
/// [first, last) are solved and listed (a block's result stays the size of the block). With a
/// plan (of this model and options) no grid envelope or analysis is made here.
std::string sweep_block(const ModelFile& model, const std::string& options_json, std::size_t first,
                        std::size_t last, nb::object progress, const SweepPlan* plan) {
  const tools::FpkSettings st = sweep_settings(model, options_json);
  fpk::SweepOptions so = sweep_options(st);
  so.block_first = first;
  so.block_last = last;
  so.plan = plan ? plan->plan.get() : nullptr;
  fpk::SweepResult sw = run_released(std::move(progress), false, [&](const ProgressCallback& cb) {
    so.progress = cb;
    return fpk::sweep(model.model, st.axes, st.grid, so);
  });
  if (last > 0) {
    const std::size_t count = sw.points.size(), lo = std::min(first, count), hi = std::min(std::max(last, lo), count);
    sw.points = std::vector<fpk::SweepPoint>(sw.points.begin() + static_cast<std::ptrdiff_t>(lo),
                                             sw.points.begin() + static_cast<std::ptrdiff_t>(hi));
  }
  return json_text(tools::sweep_to_json(sw));
}

}  // namespace

void bind_fpk(nb::module_& m) {
  m.def("stationary_region",
        [](const ModelFile& model, double log_density_drop) {
          const fpk::FpkModel fm(model.model, "vehs.plot: model");
          fpk::DomainOptions o;
          o.log_density_drop = log_density_drop;
          const fpk::Grid g = fpk::automatic_domain(fm, 3, 3, o);
          return std::vector<double>{g.x.min, g.x.max, g.y.min, g.y.max};
        },
        nb::arg("model"), nb::arg("log_density_drop"),
        "[x_min, x_max, y_min, y_max] where the stationary density stays within e^-K of its peak "
        "(fpk::automatic_domain, the rule of fpk-stationary's automatic grid).");
  m.def("mean_power",
        [](double eyy, const std::string& units, const std::string& harvester) {
          const tools::MeanPower p = tools::mean_power(eyy, nlohmann::json::parse(units), nlohmann::json::parse(harvester));
          nlohmann::ordered_json j = {{"watts", p.available ? nlohmann::json(p.watts) : nlohmann::json(nullptr)},
                                      {"how", p.formula}};
          return json_text(j);
        },
        nb::arg("eyy"), nb::arg("units"), nb::arg("harvester"),
        "fpk-stationary's mean power in W from E[Y^2] (JSON: watts, null without constants or SI units, and how).");
  nb::class_<Stationary>(m, "Stationary", "A stationary FPK density (vehs::fpk::StationaryResult).")
      .def_prop_ro("density", [](nb::handle_t<Stationary> self) {
        return view(self, nb::cast<Stationary&>(self).result->density);
      })
      .def_prop_ro("marginal_x", [](nb::handle_t<Stationary> self) {
        return view(self, nb::cast<Stationary&>(self).result->marginal_x);
      })
      .def_prop_ro("marginal_y", [](nb::handle_t<Stationary> self) {
        return view(self, nb::cast<Stationary&>(self).result->marginal_y);
      })
      .def("address", [](const Stationary& s) { return reinterpret_cast<std::uintptr_t>(s.result->density.data()); })
      .def("summary", [](const Stationary& s) {
        nlohmann::ordered_json j = tools::result_to_json(*s.result);
        j["mean_power"] = s.power;
        return json_text(j);
      });
  m.def("stationary", &stationary, nb::arg("model"), nb::arg("options"), nb::arg("progress").none());
  nb::class_<SweepPlan>(m, "SweepPlan", "A sweep's grid, point errors and symbolic analysis (vehs::fpk::SweepPlan).")
      .def_static("analysed", &analysed_plan, nb::arg("model"), nb::arg("options"), nb::arg("plan"),
                  "The plan of sweep_plan's JSON with its symbolic analysis made here.");
  m.def("sweep_plan", &sweep_plan_json, nb::arg("model"), nb::arg("options"),
        "The sweep's grid and point errors as JSON (exact doubles), to ship to the workers.");
  m.def("sweep", &sweep_block, nb::arg("model"), nb::arg("options"), nb::arg("first") = 0, nb::arg("last") = 0,
        nb::arg("progress").none(), nb::arg("plan").none() = nb::none());
}

}  // namespace vehs::python
