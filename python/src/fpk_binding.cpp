// vehs.stationary and the sweep: fpk-stationary's keys; the density handed to NumPy without a
// copy; sweeps solved whole or by blocks of points that merge exactly (SweepOptions::block_*).
#include <cstdint>

#include <nanobind/stl/string.h>

#include "bindings.hpp"
#include "bridge.hpp"
#include "records.hpp"
#include "tools/fpk_output.hpp"
#include "tools/fpk_tool.hpp"
#include "vehs/core/parameters.hpp"

namespace vehs::python {

namespace {

/// A solved density, kept for NumPy views.
struct Stationary {
  std::shared_ptr<fpk::StationaryResult> result = std::make_shared<fpk::StationaryResult>();
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
  return out;
}

/// The sweep's JSON (fpk-stationary's "sweep" section); with last > 0 only the points
/// [first, last) are solved, the others carry the error "outside the block".
std::string sweep_block(const ModelFile& model, const std::string& options_json, std::size_t first,
                        std::size_t last, nb::object progress) {
  const tools::FpkSettings st = settings(options_json, "vehs.sweep");
  require(!st.axes.empty(), "vehs.sweep: give 'sweep' (one or two parameters)");
  for (const auto& a : st.axes) (void)get_parameter(model.model, a.name);
  fpk::SweepOptions so;
  so.solve = st.solve;
  so.domain = st.domain;
  so.block_first = first;
  so.block_last = last;
  const fpk::SweepResult sw = run_released(std::move(progress), false, [&](const ProgressCallback& cb) {
    so.progress = cb;
    return fpk::sweep(model.model, st.axes, st.grid, so);
  });
  return json_text(tools::sweep_to_json(sw));
}

}  // namespace

void bind_fpk(nb::module_& m) {
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
      .def("summary", [](const Stationary& s) { return json_text(tools::result_to_json(*s.result)); });
  m.def("stationary", &stationary, nb::arg("model"), nb::arg("options"), nb::arg("progress").none());
  m.def("sweep", &sweep_block, nb::arg("model"), nb::arg("options"), nb::arg("first") = 0, nb::arg("last") = 0,
        nb::arg("progress").none());
}

}  // namespace vehs::python
